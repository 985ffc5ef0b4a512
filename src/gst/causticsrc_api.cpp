// SPDX-License-Identifier: LGPL-2.1-or-later
// The C++ side of causticsrc: what causticd hands an element and asks of it
// (causticsrc.hpp), beside GObject properties that carry only plain values.
#include "causticsrc_state.hpp"

namespace caustic::gst {

namespace {

State* checked_state(GstElement* element) {
  g_return_val_if_fail(G_TYPE_CHECK_INSTANCE_TYPE(element, gst_caustic_src_get_type()), nullptr);
  return reinterpret_cast<GstCausticSrc*>(element)->state;
}

}  // namespace

// Water given with the source moves on where it was; otherwise the scene's
// starts from its warmed-up surface. Under s.lock.
void start_water(State& s) {
  const caustic::Scene scene = s.params->snapshot().scene;
  if (!scene.water) s.pool.reset();
  else if (!s.pool) s.pool = std::make_shared<caustic::water::Pool>(*scene.water);
  s.source.pool = s.pool;
}

void set_source(GstElement* causticsrc, std::shared_ptr<ParamStore> params, std::shared_ptr<const MeshLevels> meshes,
                std::shared_ptr<water::Pool> pool) {
  if (State* s = checked_state(causticsrc)) {
    std::lock_guard lock(s->lock);
    s->params = std::move(params);
    s->meshes = std::move(meshes);
    s->pool = std::move(pool);
    s->from_file = false;
  }
}

std::optional<std::chrono::steady_clock::time_point> render_heartbeat(GstElement* causticsrc) {
  State* s = checked_state(causticsrc);
  const std::int64_t ticks = s ? s->heartbeat.load() : 0;
  if (ticks == 0) return std::nullopt;
  return std::chrono::steady_clock::time_point(std::chrono::steady_clock::duration(ticks));
}

void set_overrun_observer(GstElement* causticsrc, std::function<void()> observer) {
  if (State* s = checked_state(causticsrc)) s->on_overrun = std::move(observer);
}

void set_frame_observer(GstElement* causticsrc, FrameObserver observer) {
  // Set before streaming starts; the streaming thread reads it without a lock.
  if (State* s = checked_state(causticsrc)) s->source.observer = std::move(observer);
}

void request_snapshot(GstElement* causticsrc, SnapshotDone done) {
  State* s = checked_state(causticsrc);
  if (!s) return done(nullptr, nullptr, nullptr);
  std::lock_guard lock(s->source.snapshots->lock);
  s->source.snapshots->pending.push_back(std::move(done));
}

void send_next_frame(GstElement* causticsrc) {
  if (State* s = checked_state(causticsrc)) s->send_next = true;
}

std::shared_ptr<water::Pool> water_pool(GstElement* causticsrc) {
  State* s = checked_state(causticsrc);
  if (!s) return nullptr;
  std::lock_guard lock(s->lock);
  return s->pool;
}

std::shared_ptr<ParamStore> param_store(GstElement* causticsrc) {
  State* s = checked_state(causticsrc);
  if (!s) return nullptr;
  std::lock_guard lock(s->lock);
  return s->params;
}

GType water_solver_type() {
  static GType type = 0;
  if (g_once_init_enter(&type)) {
    static const GEnumValue values[] = {
        {static_cast<gint>(WaterSolver::automatic), "On the GL when the renderer is a GPU, else on the CPU", "auto"},
        {static_cast<gint>(WaterSolver::cpu), "On the CPU", "cpu"},
        {static_cast<gint>(WaterSolver::gl), "On the GL (compute shaders)", "gl"},
        {0, nullptr, nullptr}};
    g_once_init_leave(&type, g_enum_register_static("CausticWaterSolver", values));
  }
  return type;
}

}  // namespace caustic::gst
