// SPDX-License-Identifier: LGPL-2.1-or-later
#include "dtls_fingerprint.hpp"

#include "ascii.hpp"

#include <glib.h>

#include <algorithm>
#include <cctype>
#include <memory>

namespace caustic::server {
namespace {

struct Hash {
  const char* name;
  GChecksumType type;
  std::size_t bytes;
};
// The hashes RFC 8122 names that GChecksum computes (not sha-224, md2, md5:
// the last two are refused by RFC 8122 anyway).
constexpr Hash kHashes[] = {{"sha-1", G_CHECKSUM_SHA1, 20},
                            {"sha-256", G_CHECKSUM_SHA256, 32},
                            {"sha-384", G_CHECKSUM_SHA384, 48},
                            {"sha-512", G_CHECKSUM_SHA512, 64}};

const Hash* hash_named(std::string_view name) {
  for (const Hash& h : kHashes)
    if (name == h.name) return &h;
  return nullptr;
}

// The DER bytes of the first certificate in `pem`; empty when there is none.
std::vector<unsigned char> der_of(std::string_view pem) {
  constexpr std::string_view begin = "-----BEGIN CERTIFICATE-----", end = "-----END CERTIFICATE-----";
  const std::size_t from = pem.find(begin);
  const std::size_t to = from == std::string_view::npos ? from : pem.find(end, from);
  if (to == std::string_view::npos) return {};
  std::string base64;
  for (const char c : pem.substr(from + begin.size(), to - from - begin.size()))
    if (!std::isspace(static_cast<unsigned char>(c))) base64 += c;
  gsize size = 0;
  std::unique_ptr<guchar, decltype(&g_free)> bytes(g_base64_decode(base64.c_str(), &size), &g_free);
  return bytes ? std::vector<unsigned char>(bytes.get(), bytes.get() + size) : std::vector<unsigned char>{};
}

}  // namespace

std::optional<Fingerprint> parse_fingerprint(std::string_view value) {
  const std::size_t space = value.find(' ');
  if (space == std::string_view::npos) return std::nullopt;
  const std::string name = ascii_lower(std::string(value.substr(0, space)));
  const Hash* hash = hash_named(name);
  if (!hash) return std::nullopt;
  const std::string_view hex = value.substr(space + 1);
  // "AB:CD:...:EF": three characters a byte, less the last colon.
  if (hex.size() != 3 * hash->bytes - 1) return std::nullopt;
  Fingerprint out{hash->name, {}};
  for (std::size_t i = 0; i < hash->bytes; ++i) {
    const int hi = ascii_hex_value(hex[3 * i]), lo = ascii_hex_value(hex[3 * i + 1]);
    if (hi < 0 || lo < 0 || (i + 1 < hash->bytes && hex[3 * i + 2] != ':')) return std::nullopt;
    out.digest.push_back(static_cast<unsigned char>(16 * hi + lo));
  }
  return out;
}

bool certificate_matches(std::string_view pem, const std::vector<Fingerprint>& fingerprints) {
  const std::vector<unsigned char> der = der_of(pem);
  if (der.empty()) return false;
  for (const Fingerprint& f : fingerprints) {
    const Hash* hash = hash_named(f.hash);
    if (!hash) continue;
    std::unique_ptr<GChecksum, decltype(&g_checksum_free)> sum(g_checksum_new(hash->type), &g_checksum_free);
    g_checksum_update(sum.get(), der.data(), static_cast<gssize>(der.size()));
    std::vector<unsigned char> digest(hash->bytes);
    gsize length = digest.size();
    g_checksum_get_digest(sum.get(), digest.data(), &length);
    if (length == digest.size() && digest == f.digest) return true;
  }
  return false;
}

}  // namespace caustic::server
