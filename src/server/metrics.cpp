// SPDX-License-Identifier: LGPL-2.1-or-later
#include "metrics.hpp"

#include <sstream>

namespace caustic::server {

void Histogram::observe(double ms) {
  std::lock_guard lock(mutex_);
  for (std::size_t i = 0; i < kBoundsMs.size(); ++i)
    if (ms <= kBoundsMs[i]) ++buckets_[i];
  ++count_;
  sum_ += ms / 1000.0;
}

std::string Histogram::render(const std::string& name, const std::string& help) const {
  std::lock_guard lock(mutex_);
  std::ostringstream out;
  out << "# HELP " << name << " " << help << "\n# TYPE " << name << " histogram\n";
  for (std::size_t i = 0; i < kBoundsMs.size(); ++i)
    out << name << "_bucket{le=\"" << kBoundsMs[i] / 1000.0 << "\"} " << buckets_[i] << "\n";
  out << name << "_bucket{le=\"+Inf\"} " << count_ << "\n"
      << name << "_sum " << sum_ << "\n"
      << name << "_count " << count_ << "\n";
  return out.str();
}

std::string Metrics::render(std::size_t sessions, std::size_t connections) const {
  std::ostringstream out;
  auto counter = [&](const char* name, const char* help, std::uint64_t value) {
    out << "# HELP " << name << " " << help << "\n# TYPE " << name << " counter\n" << name << " " << value << "\n";
  };
  out << "# HELP causticd_sessions Sessions now open.\n# TYPE causticd_sessions gauge\ncausticd_sessions " << sessions
      << "\n";
  out << "# HELP causticd_connections Client connections now open.\n# TYPE causticd_connections gauge\ncausticd_connections "
      << connections << "\n";
  counter("causticd_sessions_created_total", "Sessions created.", sessions_created);
  counter("causticd_sessions_rejected_total", "Session requests refused because the server was full.",
          sessions_rejected);
  counter("causticd_frames_rendered_total", "Caustic passes drawn.", frames_rendered);
  counter("causticd_render_overruns_total", "Frames sent while a render outlasted its frame interval (the previous picture went out again).",
          render_overruns);
  counter("causticd_frames_dropped_total",
          "Frames dropped before the encoder because it was still encoding an earlier one (the newest goes next), or "
          "because nothing takes its output yet (a session before its viewer connects).",
          frames_dropped);
  counter("causticd_frames_sent_total", "Encoded frames handed to the RTP payloader.", frames_sent);
  counter("causticd_parameter_updates_total", "Accepted parameter patches.", parameter_updates);
  counter("causticd_water_drops_total", "Drops accepted into sessions' water.", water_drops);
  counter("causticd_http_errors_total", "HTTP answers with a 4xx or 5xx status.", http_errors);
  counter("causticd_pipeline_errors_total", "Errors posted by session pipelines.", pipeline_errors);
  counter("causticd_connections_accepted_total", "Client connections admitted.", connections_accepted);
  counter("causticd_connections_refused_total", "Connections answered and closed by the accept path (limits, malformed heads).",
          connections_refused);
  counter("causticd_connections_timed_out_total", "Connections closed because the request or the answer took too long.",
          connections_timed_out);
  counter("causticd_accept_failures_total", "Accepts that failed for want of file descriptors.", accept_failures);
  counter("causticd_rate_limited_total", "Requests answered 429 by the per-address rate limit.", rate_limited);
  counter("causticd_sessions_reclaimed_total", "Sessions ended because their viewer was absent or silent.",
          sessions_reclaimed);
  counter("causticd_designs_submitted_total", "Pictures accepted for design.", designs_submitted);
  counter("causticd_designs_refused_total", "Picture uploads refused (format, size, limits, queue).", designs_refused);
  out << render_ms.render("causticd_render_seconds", "Time to render one frame (caustic pass and post-processing).");
  out << encode_ms.render("causticd_encode_seconds", "Time from raw frame to encoded frame.");
  return out.str();
}

}  // namespace caustic::server
