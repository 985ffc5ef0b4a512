// SPDX-License-Identifier: LGPL-2.1-or-later
// FNV-1a, 64 bits (Fowler, Noll and Vo): a short, stable name for some
// bytes, the same on every host and in every build (std::hash is neither),
// for a calibration's fingerprint and a page's cache tag. Not a security
// boundary: anyone can make two inputs with one hash.
#pragma once

#include <cstdint>
#include <string_view>

namespace caustic {

inline constexpr std::uint64_t kFnv1aBasis = 14695981039346656037ull;  // the offset basis
inline constexpr std::uint64_t kFnv1aPrime = 1099511628211ull;

/// `h` with one more byte hashed in.
constexpr std::uint64_t fnv1a_byte(std::uint64_t h, unsigned char byte) { return (h ^ byte) * kFnv1aPrime; }

/// `h` (the offset basis for a fresh hash) with `text`'s bytes hashed in.
constexpr std::uint64_t fnv1a(std::string_view text, std::uint64_t h = kFnv1aBasis) {
  for (const char c : text) h = fnv1a_byte(h, static_cast<unsigned char>(c));
  return h;
}

}  // namespace caustic
