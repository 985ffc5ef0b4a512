// SPDX-License-Identifier: LGPL-2.1-or-later
#include "bands.hpp"

namespace caustic {

int band_cores() {
  static const int cores = static_cast<int>(std::clamp(std::thread::hardware_concurrency(), 1u, 8u));
  return cores;
}

BandCrew& band_crew() {
  thread_local BandCrew crew(band_cores() - 1);
  return crew;
}

BandCrew::BandCrew(int helpers) {
  for (int b = 1; b <= helpers; ++b) threads_.emplace_back([this, b] { serve(b); });
}

BandCrew::~BandCrew() {
  {
    std::lock_guard lock(mutex_);
    stop_ = true;
  }
  start_.notify_all();
  for (auto& t : threads_) t.join();
}

void BandCrew::run(int bands, const std::function<void(int)>& job) {
  const int handed = std::clamp(bands - 1, 0, helpers());  // bands 1..handed go to helpers
  {
    std::lock_guard lock(mutex_);
    job_ = &job;
    bands_ = handed + 1;
    pending_ = handed;
    ++generation_;
  }
  if (handed > 0) start_.notify_all();
  job(0);
  for (int b = handed + 1; b < bands; ++b) job(b);  // more bands than helpers: the caller's
  std::unique_lock lock(mutex_);
  done_.wait(lock, [this] { return pending_ == 0; });
  job_ = nullptr;
}

void BandCrew::serve(int band) {
  unsigned seen = 0;
  std::unique_lock lock(mutex_);
  for (;;) {
    start_.wait(lock, [&] { return stop_ || generation_ != seen; });
    if (stop_) return;
    seen = generation_;
    if (band >= bands_) continue;  // a job of fewer bands than helpers
    const auto* job = job_;
    lock.unlock();
    (*job)(band);
    lock.lock();
    if (--pending_ == 0) done_.notify_one();
  }
}

}  // namespace caustic
