// SPDX-License-Identifier: LGPL-2.1-or-later
// A scene's water as a stream shows it. The render thread advances the
// solver with the stream's clock, in whole fixed steps (the remainder waits
// for the next frame), and draws the surface it leaves; drops come from any
// thread and fall at the next advance; viewers get a coarse copy of the
// heights of each frame they are shown, to draw the surface in step with
// the caustic. One lock guards the queue and the copies; the solver itself
// is the render thread's alone. The render thread may hand the stepping to
// the GL (attach()), keeping a copy of the state here.
#pragma once

#include "caustic/mesh.hpp"
#include "caustic/scene.hpp"
#include "caustic/wave_solver.hpp"

#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <vector>

namespace caustic::water {

struct Drop {
  double x = 0, y = 0;  ///< metres from the pool's centre
  double strength = 0;  ///< the dent's depth, metres
  double radius = 0;    ///< its Gaussian's sigma, metres
};

/// The surface a viewer draws: `n` x `n` heights sampled evenly across the
/// pool, walls included, in units of `unit` metres, row-major with y the
/// slow index; `step` is the solver step they show, `drops` how many posted
/// drops had fallen by then.
struct Proxy {
  int n = 0;
  double unit = 1e-5;
  std::uint64_t step = 0, drops = 0;
  std::vector<std::int16_t> heights;
};

/// The same surface on an `n` x `n` grid (bilinear, walls kept): what fits
/// a datagram a relay passes on whole (16 x 16 is 512 bytes of heights).
Proxy resample(const Proxy& proxy, int n);

/// Steps the water elsewhere than the pool's own solver: on the GL
/// (caustic/wave_gl.hpp), so that a GPU moves it. Made from the pool's
/// state by the render thread, and used only with what it needs (a current
/// GL context).
class Stepper {
 public:
  virtual ~Stepper() = default;
  /// As WaveSolver::drop (throws as check_drop() does).
  virtual void drop(double x, double y, double strength, double radius) = 0;
  /// One time step, rain and wind included.
  virtual void step() = 0;
  /// Its state, read back.
  virtual WaveState state() const = 0;
};

/// Makes a stepper that goes on from `state` with `params`.
using MakeStepper = std::function<std::unique_ptr<Stepper>(const WaveParams& params, const WaveState& state)>;

/// The water after params.warmup_s of rain and wind from still water (the
/// same seed, the same surface). Throws SceneError.
WaveSolver warmed_up(const WaveParams& params);

/// The mesh a scene renders: its OBJ file, or for a scene with water the
/// surface warmed_up() leaves. Throws SceneError.
Mesh load_scene_mesh(const Scene& scene);

class Pool {
 public:
  /// Drops waiting for the next frame at most; more are refused.
  static constexpr std::size_t kMaxQueued = 64;
  /// The most water time one advance simulates: a stalled renderer slows
  /// the water down rather than owing it an ever longer catch-up.
  static constexpr double kMaxAdvance = 0.25;
  /// Frames whose proxies are kept for the viewers' messages.
  static constexpr std::size_t kProxiesKept = 16;
  static constexpr int kProxySide = 32;

  /// Still water warmed up for params.warmup_s. Throws SceneError.
  explicit Pool(const WaveParams& params);
  /// Water that was warmed up once (warmed_up()), for each stream a copy.
  explicit Pool(WaveSolver warmed);

  /// Any thread: checks the drop (SceneError naming "x", "y", "strength" or
  /// "radius") and queues it. Returns its number (1 for the first posted):
  /// it shows in the frames whose Proxy::drops reaches it. None when
  /// kMaxQueued already wait.
  std::optional<std::uint64_t> post(const Drop& drop);

  /// Render thread: takes `params` (WaveSolver::retune), lets the queued
  /// drops fall, and simulates `seconds` more (at most kMaxAdvance) unless
  /// params.paused. True when the surface changed.
  bool advance(const WaveParams& params, double seconds);

  /// Render thread, with what `make`'s steppers need: the water steps on a
  /// stepper from now on, starting from the state here (the same steps
  /// follow, to the stepper's rounding). After each advance that moved it,
  /// its state comes back here for the mesh, the proxies and detach().
  /// Throws what `make` throws, and then stays as it was.
  void attach(MakeStepper make);
  /// Render thread, as attach(): the water steps here again.
  void detach();
  bool attached() const { return stepper_ != nullptr; }

  /// Render thread: the surface now, as the engine draws it; with `stride`
  /// above 1 thinned for a preview (water_mesh.hpp). Each is built once a
  /// surface.
  std::shared_ptr<const Mesh> mesh(int stride = 1);
  /// Render thread: the solver step the surface shows.
  std::uint64_t step() const { return solver_.steps(); }
  /// Posted drops fallen so far, rain excluded (render thread).
  std::uint64_t drops() const { return drops_; }
  const WaveSolver& solver() const { return solver_; }

  /// Any thread: the coarse surface of solver step `step`, if a mesh() of
  /// it was taken recently (empty heights otherwise).
  Proxy proxy(std::uint64_t step) const;

 private:
  WaveSolver solver_;
  std::unique_ptr<Stepper> stepper_;  // when attached: what steps the water, solver_ its copy
  MakeStepper make_;
  const WaveParams shape_;  // as constructed: the grid and size drops are checked against
  double owed_ = 0;  // seconds simulated short of a whole step
  std::uint64_t drops_ = 0;
  std::shared_ptr<const Mesh> mesh_, thinned_;  // of the surface now; empty once it moves
  int thinned_stride_ = 0;
  mutable std::mutex lock_;
  std::vector<Drop> queued_;
  std::uint64_t posted_ = 0;
  std::deque<Proxy> proxies_;
};

}  // namespace caustic::water
