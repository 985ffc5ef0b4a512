// SPDX-License-Identifier: LGPL-2.1-or-later
#include "ice_setup.hpp"

#define GST_USE_UNSTABLE_API
#include <gst/webrtc/webrtc.h>

#include <cstdio>

namespace caustic::server {

std::vector<std::string> configure_ice(GstElement* webrtcbin, const ServerConfig& config) {
  std::vector<std::string> refused;
  GstWebRTCICE* ice = nullptr;
  g_object_get(webrtcbin, "ice-agent", &ice, nullptr);
  if (!ice) return config.ice_addresses;
  // libnice asks the LAN's router for port mappings (UPnP IGD) by default;
  // each agent's UPnP client costs a thread, SSDP multicast and, with
  // gssdp 1.6, a leaked socket address.
  if (g_object_class_find_property(G_OBJECT_GET_CLASS(ice), "agent")) {
    GObject* agent = nullptr;
    g_object_get(ice, "agent", &agent, nullptr);
    if (agent && g_object_class_find_property(G_OBJECT_GET_CLASS(agent), "upnp")) g_object_set(agent, "upnp", FALSE, nullptr);
    if (agent) g_object_unref(agent);
  }
  if (int lo = 0, hi = 0; std::sscanf(config.ice_port_range.c_str(), "%d-%d", &lo, &hi) == 2)
    g_object_set(ice, "min-rtp-port", static_cast<guint>(lo), "max-rtp-port", static_cast<guint>(hi), nullptr);
  for (const auto& address : config.ice_addresses) {
    gboolean ok = FALSE;
    g_signal_emit_by_name(ice, "add-local-ip-address", address.c_str(), &ok);
    if (!ok) refused.push_back(address);
  }
  gst_object_unref(ice);
  return refused;
}

}  // namespace caustic::server
