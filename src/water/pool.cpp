// SPDX-License-Identifier: LGPL-2.1-or-later
#include "caustic/pool.hpp"

#include "caustic/height_field.hpp"
#include "caustic/water_mesh.hpp"

#include <algorithm>
#include <cmath>

namespace caustic::water {
namespace {

// `side` x `side` samples of the n x n grid `at(i, j)` spans, walls included,
// bilinear, in units of `unit`.
template <typename At>
std::vector<std::int16_t> bilinear(int n, int side, double unit, const At& at) {
  std::vector<std::int16_t> out;
  out.reserve(static_cast<std::size_t>(side) * side);
  const double per = static_cast<double>(n - 1) / (side - 1);  // grid cells per sample
  for (int j = 0; j < side; ++j)
    for (int i = 0; i < side; ++i) {
      const double u = i * per, v = j * per;
      const int i0 = std::min(static_cast<int>(u), n - 2), j0 = std::min(static_cast<int>(v), n - 2);
      const double fu = u - i0, fv = v - j0;
      const double value = (1 - fv) * ((1 - fu) * at(i0, j0) + fu * at(i0 + 1, j0)) +
                           fv * ((1 - fu) * at(i0, j0 + 1) + fu * at(i0 + 1, j0 + 1));
      out.push_back(static_cast<std::int16_t>(std::clamp(std::lround(value / unit), -32767L, 32767L)));
    }
  return out;
}

Proxy sample(const WaveSolver& solver) {
  const int n = solver.params().grid;
  const auto& h = solver.heights();
  Proxy out;
  out.n = Pool::kProxySide;
  out.step = solver.steps();
  out.heights = bilinear(n, out.n, out.unit, [&](int i, int j) { return h[static_cast<std::size_t>(j) * n + i]; });
  return out;
}

}  // namespace

Proxy resample(const Proxy& proxy, int n) {
  Proxy out = proxy;
  if (proxy.heights.empty() || n == proxy.n) return out;
  out.n = n;
  out.heights = bilinear(proxy.n, n, proxy.unit, [&](int i, int j) {
    return proxy.heights[static_cast<std::size_t>(j) * proxy.n + i] * proxy.unit;
  });
  return out;
}

WaveSolver warmed_up(const WaveParams& params) {
  WaveSolver solver(params);
  while (solver.time() + 0.5 * solver.time_step() < params.warmup_s) solver.step();
  return solver;
}

Mesh load_scene_mesh(const Scene& scene) {
  return scene.water ? water_mesh(warmed_up(*scene.water)) : load_face(scene);
}

Pool::Pool(const WaveParams& params) : Pool(warmed_up(params)) {}

Pool::Pool(WaveSolver warmed) : solver_(std::move(warmed)), shape_(solver_.params()) {}

std::optional<std::uint64_t> Pool::post(const Drop& drop) {
  // The pool's grid and size never change (retune() refuses): checked
  // against the first parameters, which no other thread writes.
  check_drop(shape_, drop.x, drop.y, drop.strength, drop.radius);
  std::lock_guard hold(lock_);
  if (queued_.size() >= kMaxQueued) return std::nullopt;
  queued_.push_back(drop);
  return ++posted_;
}

void Pool::attach(MakeStepper make) {
  stepper_ = make(solver_.params(), solver_.state());
  make_ = std::move(make);
}

void Pool::detach() {
  stepper_.reset();  // its state is already here: each advance that moved it brought it back
  make_ = nullptr;
}

bool Pool::advance(const WaveParams& params, double seconds) {
  if (params != solver_.params()) {
    // Retuned here (new steps, rain or wind from the state as it is), then
    // handed to a new stepper; nothing changes when the retune throws.
    WaveSolver retuned = solver_;
    retuned.retune(params);
    std::unique_ptr<Stepper> next = stepper_ ? make_(retuned.params(), retuned.state()) : nullptr;
    solver_ = std::move(retuned);
    if (next) stepper_ = std::move(next);
  }
  std::vector<Drop> falling;
  {
    std::lock_guard hold(lock_);
    falling.swap(queued_);
  }
  for (const Drop& d : falling) {
    if (stepper_) stepper_->drop(d.x, d.y, d.strength, d.radius);
    else solver_.drop(d.x, d.y, d.strength, d.radius);
  }
  drops_ += falling.size();
  bool moved = !falling.empty();
  if (!params.paused && std::isfinite(seconds) && seconds > 0) {
    owed_ += std::min(seconds, kMaxAdvance);
    const auto steps = static_cast<std::uint64_t>(std::floor(owed_ / solver_.time_step()));
    for (std::uint64_t i = 0; i < steps; ++i) {
      if (stepper_) stepper_->step();
      else solver_.step();
    }
    owed_ -= static_cast<double>(steps) * solver_.time_step();
    moved = moved || steps > 0;
  }
  if (moved && stepper_) solver_.restore(stepper_->state());
  if (moved) mesh_.reset(), thinned_.reset();
  return moved;
}

std::shared_ptr<const Mesh> Pool::mesh(int stride) {
  stride = std::max(stride, 1);
  if (!mesh_ && !thinned_) {  // the first frame of this surface: its viewers' copy
    Proxy coarse = sample(solver_);
    coarse.drops = drops_;
    std::lock_guard hold(lock_);
    proxies_.push_back(std::move(coarse));
    while (proxies_.size() > kProxiesKept) proxies_.pop_front();
  }
  if (stride == 1) {
    if (!mesh_) mesh_ = std::make_shared<const Mesh>(water_mesh(solver_));
    return mesh_;
  }
  if (!thinned_ || thinned_stride_ != stride) {
    thinned_ = std::make_shared<const Mesh>(water_mesh(solver_, stride));
    thinned_stride_ = stride;
  }
  return thinned_;
}

Proxy Pool::proxy(std::uint64_t step) const {
  std::lock_guard hold(lock_);
  // Newest first: a drop into paused water makes a new surface at the same
  // step, and the frames after it must show it (those drawn just before it
  // get it a frame early).
  for (auto p = proxies_.rbegin(); p != proxies_.rend(); ++p)
    if (p->step == step) return *p;
  return {};
}

}  // namespace caustic::water
