// SPDX-License-Identifier: LGPL-2.1-or-later
#include "signal_message.hpp"

#include "caustic/json_text.hpp"

#include <gst/sdp/sdp.h>

#include <algorithm>
#include <sstream>
#include <string>
#include <vector>

namespace caustic::server {
namespace {

// The SDP of `text`, owned; null when it does not parse.
struct SdpMessage {
  GstSDPMessage* sdp = nullptr;
  explicit SdpMessage(std::string_view text) {
    // The parser asserts a non-empty buffer (a GLib critical, not an error).
    gst_sdp_message_new(&sdp);
    if (text.empty() || gst_sdp_message_parse_buffer(reinterpret_cast<const guint8*>(text.data()),
                                                     static_cast<guint>(text.size()), sdp) != GST_SDP_OK) {
      gst_sdp_message_free(sdp);
      sdp = nullptr;
    }
  }
  ~SdpMessage() {
    if (sdp) gst_sdp_message_free(sdp);
  }
  SdpMessage(const SdpMessage&) = delete;
  SdpMessage& operator=(const SdpMessage&) = delete;
};

bool is_sdp(const std::string& text) {
  const SdpMessage message(text);
  return message.sdp && gst_sdp_message_medias_len(message.sdp) > 0;
}

std::string text_of(const char* s) { return s ? s : ""; }

// The media's direction: its own attribute, else the session's, else
// sendrecv (RFC 3264 5.1).
std::string direction(const GstSDPMessage* sdp, const GstSDPMedia* media) {
  for (const char* d : {"sendonly", "recvonly", "sendrecv", "inactive"})
    if (gst_sdp_media_get_attribute_val(media, d)) return d;
  for (const char* d : {"sendonly", "recvonly", "sendrecv", "inactive"})
    if (gst_sdp_message_get_attribute_val(sdp, d)) return d;
  return "sendrecv";
}

// A data channel's m-line: what webrtcbin tells apart by its first format.
bool data_channel(const GstSDPMedia* media) {
  return gst_sdp_media_formats_len(media) > 0 && text_of(gst_sdp_media_get_format(media, 0)) == "webrtc-datachannel";
}

std::vector<std::string> words(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string w; in >> w;) out.push_back(w);
  return out;
}

// The mids of each "a=group:BUNDLE ..." line.
std::vector<std::vector<std::string>> bundle_groups(const GstSDPMessage* sdp) {
  std::vector<std::vector<std::string>> groups;
  for (guint i = 0; i < gst_sdp_message_attributes_len(sdp); ++i) {
    const GstSDPAttribute* a = gst_sdp_message_get_attribute(sdp, i);
    if (text_of(a->key) != "group") continue;
    std::vector<std::string> w = words(text_of(a->value));
    if (w.empty() || w.front() != "BUNDLE") continue;
    w.erase(w.begin());
    groups.push_back(std::move(w));
  }
  return groups;
}

// Whether the answer's BUNDLE groups fit the offer's: none, or one that
// starts with the offer's first bundled mid (the transport webrtcbin made)
// and names only the offer's bundled mids, each once. webrtcbin 1.22 takes
// the first mid of the answer's group for its transport and aborts when it
// names another m-line.
bool bundle_fits(const GstSDPMessage* offer, const GstSDPMessage* answer) {
  const auto offered = bundle_groups(offer), answered = bundle_groups(answer);
  if (answered.empty()) return true;
  if (answered.size() > 1 || offered.size() != 1 || answered[0].empty() || offered[0].empty() ||
      answered[0][0] != offered[0][0])
    return false;
  std::vector<std::string> seen;
  for (const std::string& mid : answered[0]) {
    if (std::find(offered[0].begin(), offered[0].end(), mid) == offered[0].end() ||
        std::find(seen.begin(), seen.end(), mid) != seen.end())
      return false;
    seen.push_back(mid);
  }
  return true;
}

}  // namespace

std::string answer_mismatch(std::string_view offer_text, std::string_view answer_text) {
  const SdpMessage offer(offer_text), answer(answer_text);
  if (!offer.sdp) return "answer: there is no offer to answer";
  if (!answer.sdp) return "answer: \"sdp\" is not valid SDP";
  const guint lines = gst_sdp_message_medias_len(offer.sdp);
  if (gst_sdp_message_medias_len(answer.sdp) != lines)
    return "answer: needs one m-line for each of the offer's " + std::to_string(lines) + ", in the offer's order";
  for (guint i = 0; i < lines; ++i) {
    const GstSDPMedia* o = gst_sdp_message_get_media(offer.sdp, i);
    const GstSDPMedia* a = gst_sdp_message_get_media(answer.sdp, i);
    const std::string media = text_of(gst_sdp_media_get_media(o)), proto = text_of(gst_sdp_media_get_proto(o));
    if (text_of(gst_sdp_media_get_media(a)) != media || text_of(gst_sdp_media_get_proto(a)) != proto ||
        data_channel(a) != data_channel(o))
      return "answer: m-line " + std::to_string(i) + " must answer the offer's " + media + " m-line (" + proto +
             (data_channel(o) ? " webrtc-datachannel" : "") + "), the m-lines in the offer's order";
    // webrtcbin finds an m-line's transport by its mid: a mid moved to
    // another m-line aborted it as a swapped order did.
    const char* mid = gst_sdp_media_get_attribute_val(o, "mid");
    if (mid && text_of(gst_sdp_media_get_attribute_val(a, "mid")) != mid)
      return "answer: m-line " + std::to_string(i) + " must keep the offer's mid (" + text_of(mid) + ")";
    if (direction(offer.sdp, o) == "sendonly" && gst_sdp_media_get_port(a) != 0) {
      const std::string d = direction(answer.sdp, a);
      if (d != "recvonly" && d != "inactive")
        return "answer: m-line " + std::to_string(i) + " answers a sendonly " + media +
               " m-line: it must be recvonly or inactive";
    }
  }
  if (!bundle_fits(offer.sdp, answer.sdp)) {
    const auto offered = bundle_groups(offer.sdp);
    const std::string first = offered.empty() || offered[0].empty() ? "" : offered[0][0];
    return "answer: a BUNDLE group must start with the offer's first bundled mid (" + first +
           ") and name only the offer's bundled mids, each once";
  }
  return "";
}

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
      const std::vector<std::string> fields = words(c);
      if (fields.size() < 8 || fields[0].rfind("candidate:", 0) != 0 || fields[6] != "typ")
        return SignalError{"ice: \"candidate\" is not an ICE candidate (candidate:... typ ...), nor \"\" for the end"};
    }
    return SignalIce{c, static_cast<unsigned>(mline->get<std::uint64_t>())};
  }
  if (type == "ping") return SignalPing{};
  return SignalError{"unknown message type"};
}

}  // namespace caustic::server
