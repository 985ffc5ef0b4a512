// SPDX-License-Identifier: LGPL-2.1-or-later
#include "address_group.hpp"

#include <gio/gio.h>

#include <array>
#include <cstring>

namespace caustic::server {

std::string address_group(const std::string& address) {
  GInetAddress* parsed = g_inet_address_new_from_string(address.c_str());
  if (!parsed) return address;
  std::string group = address;
  if (g_inet_address_get_family(parsed) == G_SOCKET_FAMILY_IPV6) {
    std::array<guint8, 16> bytes{};
    std::memcpy(bytes.data(), g_inet_address_to_bytes(parsed), bytes.size());
    static constexpr std::array<guint8, 12> kMapped{0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0xff, 0xff};
    GInetAddress* kept = nullptr;
    if (std::equal(kMapped.begin(), kMapped.end(), bytes.begin())) {
      kept = g_inet_address_new_from_bytes(bytes.data() + 12, G_SOCKET_FAMILY_IPV4);
    } else {
      std::fill(bytes.begin() + 8, bytes.end(), 0);
      kept = g_inet_address_new_from_bytes(bytes.data(), G_SOCKET_FAMILY_IPV6);
    }
    gchar* text = g_inet_address_to_string(kept);
    group = std::string(text) + (g_inet_address_get_family(kept) == G_SOCKET_FAMILY_IPV6 ? "/64" : "");
    g_free(text);
    g_object_unref(kept);
  }
  g_object_unref(parsed);
  return group;
}

}  // namespace caustic::server
