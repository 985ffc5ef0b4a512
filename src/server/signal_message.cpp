// SPDX-License-Identifier: LGPL-2.1-or-later
#include "signal_message.hpp"

#include "ascii.hpp"
#include "caustic/json_text.hpp"
#include "dtls_fingerprint.hpp"

#include <arpa/inet.h>
#include <gst/sdp/sdp.h>

#include <algorithm>
#include <cctype>
#include <set>
#include <sstream>
#include <string>
#include <string_view>
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

// How many attributes `key` has at the session level, or in `media`.
std::size_t count_attributes(const GstSDPMessage* sdp, const char* key) {
  std::size_t n = 0;
  for (guint i = 0; i < gst_sdp_message_attributes_len(sdp); ++i)
    n += text_of(gst_sdp_message_get_attribute(sdp, i)->key) == key;
  return n;
}
std::size_t count_attributes(const GstSDPMedia* media, const char* key) {
  std::size_t n = 0;
  for (guint i = 0; i < gst_sdp_media_attributes_len(media); ++i)
    n += text_of(gst_sdp_media_get_attribute(media, i)->key) == key;
  return n;
}

// A whole number in [lo, hi], as written (no sign, no wrap past 2^32).
bool number_in(const std::string& text, unsigned long long lo, unsigned long long hi) {
  if (text.empty() || text.size() > 10 || text.find_first_not_of("0123456789") != std::string::npos) return false;
  const unsigned long long n = std::stoull(text);
  return n >= lo && n <= hi;
}

// Whether a candidate's fields have RFC 8839's shape: foundation,
// component, transport, priority, address, port, "typ", type, then
// name-value pairs.
bool candidate_shape(const std::vector<std::string>& w) { return w.size() >= 8 && w[6] == "typ"; }

// An address libnice reads (an IPv4 or IPv6 literal, the latter with an
// optional zone), or a browser's mDNS name, which webrtcbin resolves.
bool candidate_address(const std::string& text) {
  if (text.size() > 6 && ascii_lower(text.substr(text.size() - 6)) == ".local") return true;
  unsigned char bytes[16];
  if (inet_pton(AF_INET, text.c_str(), bytes) == 1) return true;
  return inet_pton(AF_INET6, text.substr(0, text.find('%')).c_str(), bytes) == 1;
}

// What is wrong with a candidate of that shape, or "". libnice takes component 0 only as a programming error (a GLib
// critical), a TCP candidate without its tcptype the same, and drops any
// other component than RTP's with a warning a line: RTCP shares RTP's
// component here (rtcp-mux), so only component 1 means anything. It drops
// a candidate whose address, type or related address it cannot read
// without a word, and wraps a port past 65535 or a priority past 32 bits
// to another: each is refused here, saying why.
std::string candidate_problem(const std::vector<std::string>& w) {
  if (w[1] != "1") return "a candidate's component must be 1 (RTCP is multiplexed with RTP)";
  if (!number_in(w[3], 1, 4294967295ULL)) return "a candidate's priority must be in [1, 2^32 - 1]";
  if (!candidate_address(w[4])) return "a candidate's address must be an IP address or an mDNS name (.local)";
  if (!number_in(w[5], 0, 65535)) return "a candidate's port must be in [0, 65535]";
  if (const std::string type = ascii_lower(w[7]); type != "host" && type != "srflx" && type != "prflx" && type != "relay")
    return "a candidate's type must be host, srflx, prflx or relay";
  for (std::size_t k = 8; k + 1 < w.size(); k += 2) {
    if (w[k] == "raddr" && !candidate_address(w[k + 1]))
      return "a candidate's raddr must be an IP address or an mDNS name (.local)";
    if (w[k] == "rport" && !number_in(w[k + 1], 0, 65535)) return "a candidate's rport must be in [0, 65535]";
  }
  const std::string transport = ascii_lower(w[2]);
  if (transport == "tcp") {
    for (std::size_t k = 8; k + 1 < w.size(); k += 2)
      if (w[k] == "tcptype" && (w[k + 1] == "active" || w[k + 1] == "passive" || w[k + 1] == "so")) return "";
    return "a TCP candidate needs a tcptype of active, passive or so";
  }
  return transport == "udp" ? "" : "a candidate's transport must be UDP or TCP";
}

// What webrtcbin 1.22 and libnice take only as a programming error (a
// GLib critical) in one m-line, or "": an SSRC of 0 (or past 32 bits,
// which wraps to one), a candidate candidate_problem refuses, an fmtp
// parameter named like a caps field the m-line's attributes make (a-mid,
// extmap-1, or an attribute's own key), which empties the payload's caps.
std::string media_problem(const GstSDPMedia* media) {
  // The m-line's attribute keys, gathered once: each fmtp parameter looked
  // up among all the attributes, and its "=" searched to the end of the
  // list, made a 63 KB answer (6,400 attributes, an fmtp of 15,500
  // parameters) cost the main loop over a second, 64 of them a minute.
  std::set<std::string> keys;
  for (guint i = 0; i < gst_sdp_media_attributes_len(media); ++i) keys.insert(text_of(gst_sdp_media_get_attribute(media, i)->key));
  for (guint i = 0; i < gst_sdp_media_attributes_len(media); ++i) {
    const GstSDPAttribute* a = gst_sdp_media_get_attribute(media, i);
    const std::string key = text_of(a->key);
    const std::vector<std::string> w = words(text_of(a->value));
    if (key == "ssrc" && (w.empty() || !number_in(w[0], 1, 4294967295ULL))) return "an SSRC must be in [1, 2^32 - 1]";
    if (key == "candidate" && !candidate_shape(w)) return "an a=candidate line is not an ICE candidate (... typ ...)";
    if (key == "candidate")
      if (const std::string problem = candidate_problem(w); !problem.empty()) return problem;
    if (key != "fmtp" || w.size() < 2) continue;
    for (std::size_t at = 0; at <= w[1].size();) {  // "name=value;name=value"
      const std::size_t end = std::min(w[1].find(';', at), w[1].size());
      const std::string_view part = std::string_view(w[1]).substr(at, end - at);
      const std::string name = ascii_lower(std::string(part.substr(0, part.find('='))));
      if (name.rfind("a-", 0) == 0 || name.rfind("extmap-", 0) == 0 || keys.count(name) > 0)
        return "an fmtp parameter must not be named like an attribute (a-..., extmap-..., or the m-line's own)";
      at = end + 1;
    }
  }
  return "";
}

// An attribute's values in `media`, or where it has none, at the session
// level (RFC 8839 and 8122 allow both).
std::vector<std::string> values_of(const GstSDPMessage* sdp, const GstSDPMedia* media, const char* key) {
  std::vector<std::string> out;
  for (guint i = 0; i < gst_sdp_media_attributes_len(media); ++i)
    if (const GstSDPAttribute* a = gst_sdp_media_get_attribute(media, i); text_of(a->key) == key)
      out.push_back(text_of(a->value));
  for (guint i = 0; out.empty() && i < gst_sdp_message_attributes_len(sdp); ++i)
    if (const GstSDPAttribute* a = gst_sdp_message_get_attribute(sdp, i); text_of(a->key) == key)
      out.push_back(text_of(a->value));
  return out;
}

// What an answered m-line's transport needs, or "": ICE credentials, a
// DTLS role in the m-line itself (the answerer picks one: active or
// passive, RFC 5763 5; webrtcbin 1.22 reads no session-level one, and took
// a missing role for active, leaving both ends DTLS clients), and a
// fingerprint the server can check the certificate against (one of another
// hash beside it is ignored, RFC 8122 5). webrtcbin 1.22 refused such
// answers only in its debug log, and took any certificate.
std::string transport_problem(const GstSDPMessage* sdp, const GstSDPMedia* media) {
  for (const char* key : {"ice-ufrag", "ice-pwd"})
    if (values_of(sdp, media, key).empty()) return std::string("needs an a=") + key;
  std::vector<std::string> setup;
  for (guint i = 0; i < gst_sdp_media_attributes_len(media); ++i)
    if (const GstSDPAttribute* a = gst_sdp_media_get_attribute(media, i); text_of(a->key) == "setup")
      setup.push_back(text_of(a->value));
  if (setup.size() != 1 || (setup[0] != "active" && setup[0] != "passive"))
    return "needs one a=setup of its own, active or passive (the answer's DTLS role)";
  const auto fingerprints = values_of(sdp, media, "fingerprint");
  if (std::none_of(fingerprints.begin(), fingerprints.end(), [](const std::string& f) { return parse_fingerprint(f); }))
    return "needs an a=fingerprint of its DTLS certificate: sha-1, sha-256, sha-384 or sha-512, its digest in hex pairs";
  return "";
}

}  // namespace

std::vector<Fingerprint> answer_fingerprints(std::string_view answer_text) {
  const SdpMessage answer(answer_text);
  std::vector<Fingerprint> out;
  if (!answer.sdp) return out;
  for (guint i = 0; i < gst_sdp_message_medias_len(answer.sdp) && out.empty(); ++i) {
    const GstSDPMedia* media = gst_sdp_message_get_media(answer.sdp, i);
    if (gst_sdp_media_get_port(media) == 0) continue;  // rejected: no transport
    for (const std::string& value : values_of(answer.sdp, media, "fingerprint"))
      if (auto f = parse_fingerprint(value)) out.push_back(std::move(*f));
  }
  return out;
}

std::string answer_mismatch(std::string_view offer_text, std::string_view answer_text) {
  const SdpMessage offer(offer_text), answer(answer_text);
  if (!offer.sdp) return "answer: there is no offer to answer";
  if (!answer.sdp) return "answer: \"sdp\" is not valid SDP";
  const guint lines = gst_sdp_message_medias_len(offer.sdp);
  if (gst_sdp_message_medias_len(answer.sdp) != lines)
    return "answer: needs one m-line for each of the offer's " + std::to_string(lines) + ", in the offer's order";
  // One ICE credential of each kind at the session level, and in each
  // m-line: webrtcbin asserts (and aborts) on a second session-level one
  // when an m-line leaves its own out.
  for (const char* key : {"ice-ufrag", "ice-pwd"})
    if (count_attributes(answer.sdp, key) > 1)
      return std::string("answer: at most one session-level a=") + key;
  for (guint i = 0; i < lines; ++i) {
    const GstSDPMedia* o = gst_sdp_message_get_media(offer.sdp, i);
    const GstSDPMedia* a = gst_sdp_message_get_media(answer.sdp, i);
    // A browser answers an m-line with a few dozen attributes and an fmtp of
    // a few parameters: far more is no answer, and only costs checking.
    if (gst_sdp_media_attributes_len(a) > kMaxAnswerAttributes)
      return "answer: m-line " + std::to_string(i) + " has more than " + std::to_string(kMaxAnswerAttributes) +
             " attributes";
    for (guint k = 0; k < gst_sdp_media_attributes_len(a); ++k) {
      const GstSDPAttribute* at = gst_sdp_media_get_attribute(a, k);
      const std::string value = text_of(at->value);
      if (text_of(at->key) == "fmtp" && std::count(value.begin(), value.end(), ';') >= kMaxFmtpParameters)
        return "answer: m-line " + std::to_string(i) + " has an fmtp of more than " +
               std::to_string(kMaxFmtpParameters) + " parameters";
    }
    for (const char* key : {"ice-ufrag", "ice-pwd"})
      if (count_attributes(a, key) > 1) return "answer: m-line " + std::to_string(i) + " has more than one a=" + key;
    if (const std::string problem = media_problem(a); !problem.empty())
      return "answer: m-line " + std::to_string(i) + ": " + problem;
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
    if (gst_sdp_media_get_port(a) == 0) continue;  // rejected: no transport, no direction
    // inactive (RFC 3264 6.1) would be a session that streams nothing:
    // webrtcbin 1.22 sent the video all the same.
    if (direction(offer.sdp, o) == "sendonly" && direction(answer.sdp, a) != "recvonly")
      return "answer: m-line " + std::to_string(i) + " answers a sendonly " + media +
             " m-line: it must be recvonly (or rejected, port 0)";
    if (const std::string problem = transport_problem(answer.sdp, a); !problem.empty())
      return "answer: m-line " + std::to_string(i) + " " + problem;
  }
  if (!bundle_fits(offer.sdp, answer.sdp)) {
    const auto offered = bundle_groups(offer.sdp);
    const std::string first = offered.empty() || offered[0].empty() ? "" : offered[0][0];
    return "answer: a BUNDLE group must start with the offer's first bundled mid (" + first +
           ") and name only the offer's bundled mids, each once";
  }
  return "";
}

SignalMessage parse_signal_message(std::string_view text, std::size_t max_bytes) {
  if (text.size() > max_bytes) return SignalError{"a signalling message is at most " + std::to_string(max_bytes) + " bytes"};
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
    // A browser's candidate is some 150 characters (an mDNS name included);
    // webrtcbin keeps every one it is given until the next negotiation.
    if (c.size() > kMaxCandidateBytes)
      return SignalError{"ice: a candidate is at most " + std::to_string(kMaxCandidateBytes) + " characters"};
    for (unsigned char ch : c)
      if (ch < 0x20 || ch >= 0x7f) return SignalError{"ice: the candidate must be printable ASCII"};
    // RFC 8839's shape, "candidate:F C transport priority address port typ
    // type ...", or "" for the end of candidates: anything else would be
    // handed to the ICE agent only to be dropped without a word.
    if (!c.empty()) {
      std::vector<std::string> fields = words(c);
      if (!candidate_shape(fields) || fields[0].rfind("candidate:", 0) != 0)
        return SignalError{"ice: \"candidate\" is not an ICE candidate (candidate:... typ ...), nor \"\" for the end"};
      if (const std::string problem = candidate_problem(fields); !problem.empty()) return SignalError{"ice: " + problem};
    }
    return SignalIce{c, static_cast<unsigned>(mline->get<std::uint64_t>())};
  }
  if (type == "ping") return SignalPing{};
  return SignalError{"unknown message type"};
}

}  // namespace caustic::server
