// SPDX-License-Identifier: LGPL-2.1-or-later
#include "water_json.hpp"

namespace caustic::detail {

water::WaveParams read_water(Reader r) {
  water::WaveParams w;
  w.grid = r.integer("grid", w.grid, 16, 512);
  w.size = r.number("size", w.size, 0.05, 100);
  w.wave_speed = r.number("wave_speed", w.wave_speed, 0, 100, true);
  w.damping = r.number("damping", w.damping, 0, 100);
  w.time_step = r.number("time_step", w.time_step, 0, 1);
  w.rain_rate = r.number("rain_rate", w.rain_rate, 0, 200);
  w.rain_strength = r.number("rain_strength", w.rain_strength, -5, 5);
  w.drop_radius = r.number("drop_radius", w.drop_radius, 0, 25, true);
  w.wind_height = r.number("wind_height", w.wind_height, 0, 2);
  w.wind_direction_deg = r.number("wind_direction_deg", w.wind_direction_deg, -360, 360);
  w.wind_wavelength = r.number("wind_wavelength", w.wind_wavelength, 0, 100, true);
  // Seeds are whole numbers a double holds exactly, so that JSON round-trips them.
  // Read as the integer written: through a double, 2^53 + 1 would round
  // into the range and be stored as another seed.
  if (const json* seed = r.get("seed")) {
    if (!seed->is_number_integer()) throw SceneError(r.key("seed"), "must be a whole number");
    const bool negative = !seed->is_number_unsigned() && seed->get<std::int64_t>() < 0;
    if (negative || seed->get<std::uint64_t>() > (std::uint64_t{1} << 53))
      throw SceneError(r.key("seed"), "must be in [0, 9007199254740992], got " + seed->dump());
    w.seed = seed->get<std::uint64_t>();
  }
  w.warmup_s = r.number("warmup_s", w.warmup_s, 0, 60);
  w.paused = r.boolean("paused", w.paused);
  r.reject_unknown();
  water::validate(w);
  return w;
}

nlohmann::json water_to_json(const water::WaveParams& w) {
  return {{"grid", w.grid},
          {"size", w.size},
          {"wave_speed", w.wave_speed},
          {"damping", w.damping},
          {"time_step", w.time_step},
          {"rain_rate", w.rain_rate},
          {"rain_strength", w.rain_strength},
          {"drop_radius", w.drop_radius},
          {"wind_height", w.wind_height},
          {"wind_direction_deg", w.wind_direction_deg},
          {"wind_wavelength", w.wind_wavelength},
          {"seed", w.seed},
          {"warmup_s", w.warmup_s},
          {"paused", w.paused}};
}

}  // namespace caustic::detail
