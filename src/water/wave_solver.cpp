// SPDX-License-Identifier: LGPL-2.1-or-later
#include "caustic/wave_solver.hpp"

#include "caustic/scene.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace caustic::water {

WaveSolver::WaveSolver(const WaveParams& params) : params_(params), rain_(params, params.seed, 0) {
  validate(params_);
  derive();
  set_waves(wind_waves(params_, dt_));
  const auto cells = static_cast<std::size_t>(params_.grid) * static_cast<std::size_t>(params_.grid);
  before_.assign(cells, 0.0);
  now_.assign(cells, 0.0);
  next_.assign(cells, 0.0);
}

void WaveSolver::derive() {
  dt_ = step_seconds(params_);
  const double courant = params_.wave_speed * dt_ / spacing(params_);
  courant2_ = courant * courant;
  a_ = 0.5 * params_.damping * dt_;
}

void WaveSolver::retune(const WaveParams& params) {
  validate(params);
  if (params.grid != params_.grid) throw SceneError("water.grid", "cannot change while the water moves");
  if (params.size != params_.size) throw SceneError("water.size", "cannot change while the water moves");
  const double before = dt_;
  const bool new_rain = params.rain_rate != params_.rain_rate || params.seed != params_.seed;
  const bool new_wind = params.wind_height != params_.wind_height || params.wind_direction_deg != params_.wind_direction_deg ||
                        params.wind_wavelength != params_.wind_wavelength || params.seed != params_.seed ||
                        params.wave_speed != params_.wave_speed || params.time_step != params_.time_step ||
                        params.damping != params_.damping;
  params_ = params;
  derive();
  // The previous step sits one new step back along the same velocity.
  if (dt_ != before)
    for (std::size_t k = 0; k < now_.size(); ++k) before_[k] = now_[k] - (now_[k] - before_[k]) * (dt_ / before);
  if (new_wind) set_waves(wind_waves(params_, dt_));
  if (new_rain) rain_ = Rain(params_, params_.seed ^ steps_, time_);
}

void WaveSolver::restore(WaveState state) {
  if (state.before.size() != now_.size() || state.now.size() != now_.size())
    throw std::invalid_argument("a wave state of another grid");
  before_ = std::move(state.before);
  now_ = std::move(state.now);
  steps_ = state.steps;
  raindrops_ = state.raindrops;
  time_ = state.time;
  rain_ = state.rain;
}

void WaveSolver::drop(double x, double y, double strength, double radius) {
  check_drop(params_, x, y, strength, radius);
  const double half = params_.size / 2, dx = spacing(params_);
  const int n = params_.grid;
  // The shape falls below 1e-5 of its depth beyond 6 sigma. Added to both
  // steps: at rest, the drop adds no velocity.
  const int reach = static_cast<int>(std::ceil(6 * radius / dx));
  const int ci = static_cast<int>(std::lround((x + half) / dx)), cj = static_cast<int>(std::lround((y + half) / dx));
  double sum = 0;
  for (int j = std::max(0, cj - reach); j <= std::min(n - 1, cj + reach); ++j)
    for (int i = std::max(0, ci - reach); i <= std::min(n - 1, ci + reach); ++i) {
      const double px = -half + i * dx - x, py = -half + j * dx - y;
      const double q = (px * px + py * py) / (2 * radius * radius);
      const double h = -strength * (1 - q) * std::exp(-q);
      const std::size_t k = static_cast<std::size_t>(j) * n + i;
      now_[k] += h;
      before_[k] += h;
      sum += trapezoid_weight(i, j, n) * h;
    }
  // Walls cut the rim: take the remainder off everywhere, keeping the volume.
  // The trapezoidal weights add up to (n - 1)^2.
  const double mean = sum / (static_cast<double>(n - 1) * (n - 1));
  for (std::size_t k = 0; k < now_.size(); ++k) {
    now_[k] -= mean;
    before_[k] -= mean;
  }
}

void WaveSolver::rain() {
  raindrops_ += static_cast<std::uint64_t>(
      rain_.fall_until(time_, [&](double x, double y) { drop(x, y, params_.rain_strength, params_.drop_radius); }));
}

void WaveSolver::set_waves(std::vector<Wave> waves) {
  if (waves.empty()) forcing_.reset();
  else forcing_.emplace(params_, dt_, std::move(waves));
}

void WaveSolver::step() {
  rain();
  if (forcing_) {
    forcing_->evaluate(time_, force_);
    // Waves the walls do not fit would pump water in or out: the wind keeps
    // the volume, as a drop does, less its (trapezoidal) mean.
    const int n = params_.grid;
    double sum = 0;
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) sum += trapezoid_weight(i, j, n) * force_[static_cast<std::size_t>(j) * n + i];
    const double mean = sum / (static_cast<double>(n - 1) * (n - 1));
    for (double& f : force_) f -= mean;
  }
  const int n = params_.grid;
  const double keep = 1 - a_, scale = 1 / (1 + a_);
  for (int j = 0; j < n; ++j) {
    // A wall's ghost row mirrors the row inside it.
    const std::size_t row = static_cast<std::size_t>(j) * n;
    const std::size_t down = static_cast<std::size_t>(mirrored(j - 1, n)) * n;
    const std::size_t up = static_cast<std::size_t>(mirrored(j + 1, n)) * n;
    for (int i = 0; i < n; ++i) {
      const int left = mirrored(i - 1, n), right = mirrored(i + 1, n);
      const double h = now_[row + i];
      const double laplacian = now_[row + left] + now_[row + right] + now_[down + i] + now_[up + i] - 4 * h;
      const double drive = forcing_ ? force_[row + i] : 0.0;
      next_[row + i] = (2 * h - keep * before_[row + i] + courant2_ * laplacian + drive) * scale;
    }
  }
  std::swap(before_, now_);
  std::swap(now_, next_);
  ++steps_;
  time_ += dt_;
}

double scheme_energy(const WaveParams& params, double dt, const std::vector<double>& before,
                     const std::vector<double>& now) {
  const int n = params.grid;
  const double dx = spacing(params);
  const double c2 = params.wave_speed * params.wave_speed;
  double kinetic = 0, potential = 0;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const std::size_t k = static_cast<std::size_t>(j) * n + i;
      const double v = (now[k] - before[k]) / dt;
      kinetic += trapezoid_weight(i, j, n) * v * v;
      // Edges to the right and up; an edge along a wall weighs a half.
      if (i + 1 < n) potential += (j == 0 || j == n - 1 ? 0.5 : 1.0) * (now[k + 1] - now[k]) * (before[k + 1] - before[k]);
      if (j + 1 < n) potential += (i == 0 || i == n - 1 ? 0.5 : 1.0) * (now[k + n] - now[k]) * (before[k + n] - before[k]);
    }
  return 0.5 * dx * dx * kinetic + 0.5 * c2 * potential;
}

double trapezoidal_volume(const WaveParams& params, const std::vector<double>& heights) {
  const int n = params.grid;
  const double dx = spacing(params);
  double sum = 0;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) sum += trapezoid_weight(i, j, n) * heights[static_cast<std::size_t>(j) * n + i];
  return sum * dx * dx;
}

double WaveSolver::energy() const { return scheme_energy(params_, dt_, before_, now_); }

double WaveSolver::volume() const { return trapezoidal_volume(params_, now_); }

}  // namespace caustic::water
