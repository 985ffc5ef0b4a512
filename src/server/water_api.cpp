// SPDX-License-Identifier: LGPL-2.1-or-later
// A session's water over HTTP: POST /api/v1/sessions/{id}/drops drops a
// stone in it (docs/api.md), and each frame's message carries the surface
// the viewer draws.
#include "caustic/json_text.hpp"
#include "caustic/pool.hpp"
#include "http_util.hpp"
#include "server_state.hpp"

#include <glib.h>

#include <algorithm>
#include <iterator>

namespace caustic::server {
namespace {

// The body's keys, with the scene's rain for what it leaves out.
const char* const kDropKeys[] = {"x", "y", "strength", "radius"};

}  // namespace

nlohmann::json water_message(const water::Proxy& proxy) {
  std::vector<guchar> bytes;
  bytes.reserve(2 * proxy.heights.size());
  for (const std::int16_t h : proxy.heights) {
    const auto u = static_cast<std::uint16_t>(h);
    bytes.push_back(static_cast<guchar>(u & 0xff));
    bytes.push_back(static_cast<guchar>(u >> 8));
  }
  gchar* text = g_base64_encode(bytes.data(), bytes.size());
  nlohmann::json out{{"step", proxy.step}, {"drops", proxy.drops}, {"n", proxy.n}, {"unit", proxy.unit},
                     {"heights", text}};
  g_free(text);
  return out;
}

void post_drop(ServerState& s, SoupServerMessage* msg, Session& session) {
  water::Pool* pool = session.water();
  if (!pool) return reply_problem(msg, s.metrics, SOUP_STATUS_CONFLICT, "this session's scene has no water");
  nlohmann::json body;
  if (!read_json_body(s, msg, {"application/json"}, &body)) return;
  for (const auto& [key, value] : body.items())
    if (std::find_if(std::begin(kDropKeys), std::end(kDropKeys), [&](const char* k) { return key == k; }) ==
        std::end(kDropKeys))
      return reply_problem(msg, s.metrics, SOUP_STATUS_UNPROCESSABLE_ENTITY, printable_name(key) + ": unknown key",
                           printable_name(key));
  const Scene scene = session.params().snapshot().scene;
  if (!scene.water) return reply_problem(msg, s.metrics, SOUP_STATUS_CONFLICT, "this session's scene has no water");
  water::Drop drop{0, 0, scene.water->rain_strength, scene.water->drop_radius};
  double* fields[] = {&drop.x, &drop.y, &drop.strength, &drop.radius};
  for (std::size_t i = 0; i < std::size(kDropKeys); ++i) {
    const char* key = kDropKeys[i];
    if (!body.contains(key)) {
      if (i < 2) return reply_problem(msg, s.metrics, SOUP_STATUS_UNPROCESSABLE_ENTITY, std::string(key) + ": is required", key);
      continue;
    }
    if (!body[key].is_number())
      return reply_problem(msg, s.metrics, SOUP_STATUS_UNPROCESSABLE_ENTITY, std::string(key) + ": must be a number", key);
    *fields[i] = body[key].get<double>();
  }
  std::optional<std::uint64_t> number;
  try {
    number = pool->post(drop);
  } catch (const SceneError& e) {
    return reply_problem(msg, s.metrics, SOUP_STATUS_UNPROCESSABLE_ENTITY, e.what(), e.key());
  }
  if (!number) {
    soup_message_headers_replace(soup_server_message_get_response_headers(msg), "Retry-After", "1");
    return reply_problem(msg, s.metrics, 429, "drops are falling faster than frames take them; retry after 1 s");
  }
  ++s.metrics.water_drops;
  reply_json(msg, SOUP_STATUS_ACCEPTED,
             {{"drop", *number}, {"x", drop.x}, {"y", drop.y}, {"strength", drop.strength}, {"radius", drop.radius}});
}

}  // namespace caustic::server
