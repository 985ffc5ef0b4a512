// SPDX-License-Identifier: LGPL-2.1-or-later
#include "signal_message.hpp"

#include "caustic/json_text.hpp"

#include <gst/sdp/sdp.h>

#include <sstream>
#include <string>
#include <vector>

namespace caustic::server {
namespace {

bool is_sdp(const std::string& text) {
  // The parser asserts a non-empty buffer (a GLib critical, not an error).
  if (text.empty()) return false;
  GstSDPMessage* sdp = nullptr;
  gst_sdp_message_new(&sdp);
  const bool ok = gst_sdp_message_parse_buffer(reinterpret_cast<const guint8*>(text.data()),
                                               static_cast<guint>(text.size()), sdp) == GST_SDP_OK &&
                  gst_sdp_message_medias_len(sdp) > 0;
  gst_sdp_message_free(sdp);
  return ok;
}

}  // namespace

SignalMessage parse_signal_message(std::string_view text) {
  if (text.size() > kMaxSignalMessageBytes)
    return SignalError{"a signalling message is at most " + std::to_string(kMaxSignalMessageBytes) + " bytes"};
  JsonTextError error;
  const auto message = parse_json_text(text, &error, 4);
  if (!message || !message->is_object() || !message->contains("type") || !(*message)["type"].is_string())
    return SignalError{"a signalling message is a JSON object with a string \"type\""};
  const std::string& type = (*message)["type"].get_ref<const std::string&>();
  if (type == "answer") {
    const auto sdp = message->find("sdp");
    if (sdp == message->end() || !sdp->is_string()) return SignalError{"answer: \"sdp\" must be a string"};
    if (!is_sdp(sdp->get<std::string>())) return SignalError{"answer: \"sdp\" is not valid SDP"};
    return SignalAnswer{sdp->get<std::string>()};
  }
  if (type == "ice") {
    const auto candidate = message->find("candidate");
    const auto mline = message->find("sdpMLineIndex");
    if (candidate == message->end() || !candidate->is_string() || mline == message->end() ||
        !mline->is_number_unsigned() || mline->get<std::uint64_t>() > 63)
      return SignalError{"ice: needs a string \"candidate\" and an \"sdpMLineIndex\" in [0, 63]"};
    const std::string& c = candidate->get_ref<const std::string&>();
    for (unsigned char ch : c)
      if (ch < 0x20 || ch >= 0x7f) return SignalError{"ice: the candidate must be printable ASCII"};
    // RFC 8839's shape, "candidate:F C transport priority address port typ
    // type ...", or "" for the end of candidates: anything else would be
    // handed to the ICE agent only to be dropped without a word.
    if (!c.empty()) {
      std::vector<std::string> fields;
      std::istringstream words(c);
      for (std::string w; words >> w;) fields.push_back(w);
      if (fields.size() < 8 || fields[0].rfind("candidate:", 0) != 0 || fields[6] != "typ")
        return SignalError{"ice: \"candidate\" is not an ICE candidate (candidate:... typ ...), nor \"\" for the end"};
    }
    return SignalIce{c, static_cast<unsigned>(mline->get<std::uint64_t>())};
  }
  if (type == "ping") return SignalPing{};
  return SignalError{"unknown message type"};
}

}  // namespace caustic::server
