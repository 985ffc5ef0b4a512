// SPDX-License-Identifier: LGPL-2.1-or-later
// Whether an address is one of this host's: ICE gathers candidates only on
// addresses its interfaces hold, so an ice_addresses entry that none holds
// (a typo, another machine's address) leaves sessions with nothing to
// connect through, and says so nowhere else.
#pragma once

#include <string>

namespace caustic::server {

/// True when a network interface of this host holds `address` (IPv4 or
/// IPv6 text); false for text that is no address.
bool host_has_address(const std::string& address);

}  // namespace caustic::server
