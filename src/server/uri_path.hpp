// SPDX-License-Identifier: LGPL-2.1-or-later
// The path a request is routed by, from the path part of its target as
// sent: "." and ".." segments resolved as the HTTP library's URI parse
// resolves them, then the escapes of unreserved characters decoded and the
// others' hex digits put in upper case (RFC 3986 5.2.4, 6.2.2). The
// handlers route by it, and so does the check of a request's head before
// its body is read: a limit chosen by the path must see the path the
// handler will, or a route written another way ("%64esigns", "./designs")
// meets another route's limit.
#pragma once

#include <string>
#include <string_view>

namespace caustic::server {

/// `path` (percent-encoded, without the query) as the router sees it.
std::string routed_path(std::string_view path);

}  // namespace caustic::server
