// SPDX-License-Identifier: LGPL-2.1-or-later
#include "caustic/wave_gl.hpp"

#include "caustic/scene.hpp"
#include "gl_objects.hpp"

#include <array>
#include <cmath>
#include <complex>
#include <stdexcept>
#include <utility>

namespace caustic::water {
namespace {

constexpr int kGroup = 16;  // the shaders' local size, each way
static_assert(kWindWaves <= 32, "wave_step.comp takes 32 waves at most");

gl::Buffer floats(std::size_t count, const float* data = nullptr) {
  gl::Buffer buffer;
  std::vector<float> zeros;
  if (!data) zeros.assign(count, 0.0f);
  glNamedBufferStorage(buffer.id(), static_cast<GLsizeiptr>(count * sizeof(float)), data ? data : zeros.data(),
                       GL_DYNAMIC_STORAGE_BIT);
  return buffer;
}

}  // namespace

struct WaveSolverGl::State {
  WaveParams params;
  double dt = 0, courant2 = 0, a = 0, time = 0;
  std::uint64_t steps = 0, raindrops = 0;
  Rain rain;
  std::vector<Wave> waves;
  // Per wave: its force's factor, and the trapezoidal sums of its row and
  // column factors (the force's mean is their product).
  std::vector<std::complex<double>> force, row_sum, column_sum;
  gl::Program step{{{GL_COMPUTE_SHADER, {"wave_step.comp"}}}};
  gl::Program drop{{{GL_COMPUTE_SHADER, {"wave_drop.comp"}}}};
  std::array<gl::Buffer, 3> heights;  // before, now, next: rotated each step
  gl::Buffer rows, columns;

  explicit State(const WaveParams& p) : params(p), rain(p, p.seed, 0) {}
  std::vector<double> read(int which) const {
    const auto cells = static_cast<std::size_t>(params.grid) * static_cast<std::size_t>(params.grid);
    std::vector<float> floats(cells);
    glGetNamedBufferSubData(at(which).id(), 0, static_cast<GLsizeiptr>(cells * sizeof(float)), floats.data());
    gl::check_errors("reading the GL wave solver's heights back");
    return {floats.begin(), floats.end()};
  }
  const gl::Buffer& at(int which) const { return heights[static_cast<std::size_t>((steps + which) % 3)]; }
  void dispatch() const {
    const GLuint groups = static_cast<GLuint>((params.grid + kGroup - 1) / kGroup);
    glDispatchCompute(groups, groups, 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
  }
};

WaveSolverGl::WaveSolverGl(const WaveParams& params) {
  validate(params);
  state_ = std::make_unique<State>(params);
  State& s = *state_;
  const int n = params.grid;
  s.dt = step_seconds(params);
  const double courant = params.wave_speed * s.dt / spacing(params);
  s.courant2 = courant * courant;
  s.a = 0.5 * params.damping * s.dt;
  s.waves = wind_waves(params, s.dt);
  const auto cells = static_cast<std::size_t>(n) * static_cast<std::size_t>(n);
  for (auto& buffer : s.heights) buffer = floats(cells);
  // exp(i k x) along the rows and the columns, wave by wave, as in Forcing.
  const double dx = spacing(params), half = params.size / 2;
  std::vector<float> rows, columns;
  for (const Wave& w : s.waves) {
    std::complex<double> row_sum = 0, column_sum = 0;
    for (int i = 0; i < n; ++i) {
      const double x = -half + i * dx, edge = i == 0 || i == n - 1 ? 0.5 : 1.0;
      const auto r = std::polar(1.0, w.kx * x), c = std::polar(1.0, w.ky * x);
      rows.insert(rows.end(), {static_cast<float>(r.real()), static_cast<float>(r.imag())});
      columns.insert(columns.end(), {static_cast<float>(c.real()), static_cast<float>(c.imag())});
      row_sum += edge * r;
      column_sum += edge * c;
    }
    s.row_sum.push_back(row_sum);
    s.column_sum.push_back(column_sum);
  }
  rows.resize(std::max<std::size_t>(rows.size(), 2));
  columns.resize(rows.size());
  s.rows = floats(rows.size(), rows.data());
  s.columns = floats(columns.size(), columns.data());
  gl::check_errors("the GL wave solver's buffers");
}

WaveSolverGl::WaveSolverGl(const WaveParams& params, const WaveState& state) : WaveSolverGl(params) {
  const auto cells = static_cast<std::size_t>(params.grid) * static_cast<std::size_t>(params.grid);
  if (state.before.size() != cells || state.now.size() != cells)
    throw std::invalid_argument("a wave state of another grid");
  State& s = *state_;
  s.steps = state.steps;
  s.raindrops = state.raindrops;
  s.time = state.time;
  s.rain = state.rain;
  // Before and now where the rotation finds them at this step count.
  for (const auto& [which, heights] : {std::pair{0, &state.before}, std::pair{1, &state.now}}) {
    const std::vector<float> floats(heights->begin(), heights->end());
    glNamedBufferSubData(s.at(which).id(), 0, static_cast<GLsizeiptr>(cells * sizeof(float)), floats.data());
  }
  gl::check_errors("the GL wave solver's state");
}

WaveSolverGl::~WaveSolverGl() = default;

void WaveSolverGl::drop(double x, double y, double strength, double radius) {
  State& s = *state_;
  check_drop(s.params, x, y, strength, radius);
  const int n = s.params.grid;
  const double half = s.params.size / 2, dx = spacing(s.params);
  // The reach and the volume remainder as WaveSolver::drop finds them.
  const int reach = static_cast<int>(std::ceil(6 * radius / dx));
  const int ci = static_cast<int>(std::lround((x + half) / dx)), cj = static_cast<int>(std::lround((y + half) / dx));
  const int i0 = std::max(0, ci - reach), i1 = std::min(n - 1, ci + reach);
  const int j0 = std::max(0, cj - reach), j1 = std::min(n - 1, cj + reach);
  double sum = 0;
  for (int j = j0; j <= j1; ++j)
    for (int i = i0; i <= i1; ++i) {
      const double px = -half + i * dx - x, py = -half + j * dx - y;
      const double q = (px * px + py * py) / (2 * radius * radius);
      sum += trapezoid_weight(i, j, n) * -strength * (1 - q) * std::exp(-q);
    }
  const gl::Program& p = s.drop;
  p.use();
  p.set("uGrid", n);
  p.set("uHalf", static_cast<float>(half));
  p.set("uSpacing", static_cast<float>(dx));
  p.set("uCentre", glm::vec2(static_cast<float>(x), static_cast<float>(y)));
  p.set("uStrength", static_cast<float>(strength));
  p.set("uRadius", static_cast<float>(radius));
  glProgramUniform4i(p.id(), glGetUniformLocation(p.id(), "uReach"), i0, j0, i1, j1);
  p.set("uMean", static_cast<float>(sum / (static_cast<double>(n - 1) * (n - 1))));
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, s.at(0).id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, s.at(1).id());
  s.dispatch();
}

void WaveSolverGl::step() {
  State& s = *state_;
  const WaveParams& params = s.params;
  s.raindrops += static_cast<std::uint64_t>(
      s.rain.fall_until(s.time, [&](double x, double y) { drop(x, y, params.rain_strength, params.drop_radius); }));
  const int n = params.grid;
  // Each wave's dt^2 f = Im(exp(i k.x) c), c = gamma dt a sin(omega dt) exp(i (phase - omega t)).
  std::array<float, 64> coefficient{};
  std::complex<double> mean = 0;
  for (std::size_t w = 0; w < s.waves.size(); ++w) {
    const Wave& v = s.waves[w];
    const auto c = std::polar(params.damping * s.dt * v.amplitude * std::sin(v.omega * s.dt), v.phase - v.omega * s.time);
    coefficient[2 * w] = static_cast<float>(c.real());
    coefficient[2 * w + 1] = static_cast<float>(c.imag());
    mean += c * s.row_sum[w] * s.column_sum[w];
  }
  const gl::Program& p = s.step;
  p.use();
  p.set("uGrid", n);
  p.set("uCourant2", static_cast<float>(s.courant2));
  p.set("uKeep", static_cast<float>(1 - s.a));
  p.set("uScale", static_cast<float>(1 / (1 + s.a)));
  p.set("uWaves", static_cast<int>(s.waves.size()));
  glProgramUniform2fv(p.id(), glGetUniformLocation(p.id(), "uCoefficient"), 32, coefficient.data());
  p.set("uMean", static_cast<float>(mean.imag() / (static_cast<double>(n - 1) * (n - 1))));
  for (int b = 0; b < 3; ++b) glBindBufferBase(GL_SHADER_STORAGE_BUFFER, static_cast<GLuint>(b), s.at(b).id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 3, s.rows.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 4, s.columns.id());
  s.dispatch();
  ++s.steps;  // the next buffer becomes the newest: before, now, next rotate
  s.time += s.dt;
}

const WaveParams& WaveSolverGl::params() const { return state_->params; }
double WaveSolverGl::time_step() const { return state_->dt; }
double WaveSolverGl::time() const { return state_->time; }
std::uint64_t WaveSolverGl::steps() const { return state_->steps; }
std::uint64_t WaveSolverGl::raindrops() const { return state_->raindrops; }

void WaveSolverGl::finish() const { glFinish(); }

std::vector<double> WaveSolverGl::heights() const { return state_->read(1); }

WaveState WaveSolverGl::state() const {
  const State& s = *state_;
  return {s.read(0), s.read(1), s.steps, s.raindrops, s.time, s.rain};
}

}  // namespace caustic::water
