// SPDX-License-Identifier: LGPL-2.1-or-later
#include "caustic/wind.hpp"

#include "caustic/rain.hpp"

#include <cmath>
#include <numbers>

namespace caustic::water {

double scheme_omega(const WaveParams& p, double dt, double kx, double ky) {
  const double dx = spacing(p);
  const double s = p.wave_speed * dt / dx * std::hypot(std::sin(kx * dx / 2), std::sin(ky * dx / 2));
  return 2 / dt * std::asin(std::min(s, 1.0));
}

std::vector<Wave> wind_waves(const WaveParams& p, double dt) {
  std::vector<Wave> out;
  if (p.wind_height <= 0) return out;
  std::uint64_t rng = p.seed ^ 0x77696e64ULL;  // "wind"
  const double kp = 2 * std::numbers::pi / p.wind_wavelength;
  const double heading = p.wind_direction_deg * std::numbers::pi / 180;
  double power = 0;
  for (int w = 0; w < kWindWaves; ++w) {
    const double k = kp * std::exp2(2 * uniform(rng) - 1);
    // cos^2 spread within a half-turn of the wind, by rejection.
    double spread = 0;
    do spread = (uniform(rng) - 0.5) * std::numbers::pi;
    while (uniform(rng) > std::cos(spread) * std::cos(spread));
    const double r = kp / k, theta = heading + spread;
    Wave wave{k * std::cos(theta), k * std::sin(theta), std::sqrt(std::exp(-r * r) * r * r), 2 * std::numbers::pi * uniform(rng), 0};
    wave.omega = scheme_omega(p, dt, wave.kx, wave.ky);
    power += wave.amplitude * wave.amplitude / 2;
    out.push_back(wave);
  }
  // Random phases: the mean square of a sum of cosines is the sum of a^2 / 2.
  for (auto& wave : out) wave.amplitude *= p.wind_height / std::sqrt(power);
  return out;
}

Forcing::Forcing(const WaveParams& p, double dt, std::vector<Wave> waves)
    : n_(p.grid), dt_(dt), gamma_(p.damping), waves_(std::move(waves)) {
  const auto count = waves_.size();
  const double dx = spacing(p), half = p.size / 2;
  rows_.resize(static_cast<std::size_t>(n_) * count);
  columns_.resize(rows_.size());
  for (int i = 0; i < n_; ++i)
    for (std::size_t w = 0; w < count; ++w) {
      const double x = -half + i * dx;
      rows_[static_cast<std::size_t>(i) * count + w] = std::polar(1.0, waves_[w].kx * x);
      columns_[static_cast<std::size_t>(i) * count + w] = std::polar(1.0, waves_[w].ky * x);
    }
  rows_re_.resize(rows_.size());
  rows_im_.resize(rows_.size());
  for (int i = 0; i < n_; ++i)
    for (std::size_t w = 0; w < count; ++w) {
      rows_re_[w * n_ + i] = rows_[static_cast<std::size_t>(i) * count + w].real();
      rows_im_[w * n_ + i] = rows_[static_cast<std::size_t>(i) * count + w].imag();
    }
}

void Forcing::evaluate(double t, std::vector<double>& out) const {
  const auto count = waves_.size();
  out.assign(static_cast<std::size_t>(n_) * n_, 0.0);
  // h*(t + dt) - h*(t - dt) = 2 a sin(omega dt) sin(theta - omega t) for each wave.
  std::vector<std::complex<double>> now(count);
  for (std::size_t w = 0; w < count; ++w) {
    const Wave& v = waves_[w];
    now[w] = std::polar(gamma_ * dt_ * v.amplitude * std::sin(v.omega * dt_), v.phase - v.omega * t);
  }
  // A row at a time, wave by wave: each point still sums its waves in
  // order from 0 (the same value to the bit as a sum per point), and the
  // compiler vectorises along the row.
  std::vector<std::complex<double>> column(count);
  for (int j = 0; j < n_; ++j) {
    for (std::size_t w = 0; w < count; ++w) column[w] = columns_[static_cast<std::size_t>(j) * count + w] * now[w];
    double* row_out = out.data() + static_cast<std::size_t>(j) * n_;
    for (std::size_t w = 0; w < count; ++w) {
      const double ci = column[w].imag(), cr = column[w].real();
      const double* re = rows_re_.data() + w * n_;
      const double* im = rows_im_.data() + w * n_;
      for (int i = 0; i < n_; ++i) row_out[i] += re[i] * ci + im[i] * cr;
    }
  }
}

double Forcing::target(double t, int i, int j) const {
  const auto count = waves_.size();
  double h = 0;
  for (std::size_t w = 0; w < count; ++w) {
    const auto e = rows_[static_cast<std::size_t>(i) * count + w] * columns_[static_cast<std::size_t>(j) * count + w] *
                   std::polar(1.0, waves_[w].phase - waves_[w].omega * t);
    h += waves_[w].amplitude * e.real();
  }
  return h;
}

}  // namespace caustic::water
