// SPDX-License-Identifier: LGPL-2.1-or-later
// What the limits per client address count: an IPv4 address, or an IPv6
// address's /64. One IPv6 subscriber is given a /64 (RFC 6177) and may take
// any address in it, so counted one by one every connection, session,
// upload and request could come from a fresh address, and no limit per
// address would hold.
#pragma once

#include <string>

namespace caustic::server {

/// "192.0.2.1" for IPv4 (and IPv4-mapped IPv6, ::ffff:192.0.2.1), the
/// prefix "2001:db8:1:2::/64" for any IPv6 address in it; what is not an
/// address (the "unknown" of a peer the library could not name) as it is.
std::string address_group(const std::string& address);

}  // namespace caustic::server
