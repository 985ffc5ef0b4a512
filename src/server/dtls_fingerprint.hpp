// SPDX-License-Identifier: LGPL-2.1-or-later
// The viewer's DTLS certificate held against its answer's a=fingerprint
// (RFC 8122, RFC 8842 5.1). The certificates are self-signed, so the
// fingerprint the signalling carried is all that ties the media's peer to
// the viewer who holds the token; webrtcbin 1.22 takes any certificate, so
// the session checks it once DTLS has connected.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace caustic::server {

struct Fingerprint {
  std::string hash;                  ///< "sha-1", "sha-256", "sha-384" or "sha-512"
  std::vector<unsigned char> digest;  ///< as many bytes as the hash gives
};

/// An a=fingerprint value, "sha-256 AB:CD:...": the hash function (any
/// case) one of the four GLib computes, and exactly its digest's length in
/// colon-separated hex pairs. nullopt otherwise.
std::optional<Fingerprint> parse_fingerprint(std::string_view value);

/// Whether the PEM certificate's digest under some fingerprint's hash is
/// that fingerprint's digest. False for no fingerprints or no certificate.
bool certificate_matches(std::string_view pem, const std::vector<Fingerprint>& fingerprints);

}  // namespace caustic::server
