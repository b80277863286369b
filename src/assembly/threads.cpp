#include "assembly/threads.hpp"

#include <sys/resource.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <string>
#include <unistd.h>

#ifdef _OPENMP
#include <omp.h>
#endif

namespace conserve::assembly {

int threads() {
#ifdef _OPENMP
  return omp_get_max_threads();
#else
  return 1;
#endif
}

bool set_threads(int threads) {
#ifdef _OPENMP
  omp_set_num_threads(threads < 1 ? 1 : threads);
  return true;
#else
  (void)threads;
  return false;
#endif
}

int processors() {
#ifdef _OPENMP
  return std::max(omp_get_num_procs(), 1);
#else
  return 1;
#endif
}

OtherLoad::OtherLoad() : last_(read()) {}

std::optional<OtherLoad::Reading> OtherLoad::read() {
  std::ifstream stat("/proc/stat");
  std::string label;
  if (!(stat >> label) || label != "cpu") return std::nullopt;
  // user nice system idle iowait irq softirq steal (guest time is in user)
  double field[8] = {};
  for (double& f : field)
    if (!(stat >> f)) return std::nullopt;
  const double ticks = static_cast<double>(sysconf(_SC_CLK_TCK));
  if (!(ticks > 0.0)) return std::nullopt;
  rusage own{};
  getrusage(RUSAGE_SELF, &own);
  const auto seconds = [](const timeval& t) { return static_cast<double>(t.tv_sec) + 1e-6 * static_cast<double>(t.tv_usec); };
  Reading r;
  r.wall = std::chrono::steady_clock::now();
  r.busy = (field[0] + field[1] + field[2] + field[5] + field[6] + field[7]) / ticks;
  r.own = seconds(own.ru_utime) + seconds(own.ru_stime);
  return r;
}

std::optional<double> OtherLoad::sample(double min_seconds) {
  if (!last_ || std::chrono::duration<double>(std::chrono::steady_clock::now() - last_->wall).count() < min_seconds)
    return std::nullopt;  // called every step: /proc/stat is read only once the window has passed
  const auto now = read();
  if (!now) return std::nullopt;
  const double wall = std::chrono::duration<double>(now->wall - last_->wall).count();
  if (!(wall > 0.0)) return std::nullopt;
  const double others = ((now->busy - last_->busy) - (now->own - last_->own)) / wall;
  last_ = now;
  return std::max(others, 0.0);
}

int ThreadGovernor::free_cores(int cores, double others) {
  return std::max(1, cores - static_cast<int>(std::ceil(std::max(others - kFreeCoreSlack, 0.0))));
}

ThreadGovernor::ThreadGovernor(int requested, int cells) {
  if (requested > 0) {
    policy_ = "[solver] threads";
    use(requested);
  } else if (std::getenv("OMP_NUM_THREADS")) {
    policy_ = "OMP_NUM_THREADS";
    use(assembly::threads());  // the OpenMP variable's count, as OpenMP read it
  } else if (cells < kMinParallelCells || processors() == 1) {
    policy_ = cells < kMinParallelCells ? "small model" : "one processor";
    use(1);
  } else if (!load_.available()) {  // no measurement (not Linux): every processor
    policy_ = "load not measurable";
    use(processors());
  } else {
    automatic_ = true;
    use(1);
  }
  fewest_ = most_ = threads_;
}

void ThreadGovernor::update() {
  if (!automatic_) return;
  const auto others = load_.sample(wait_);
  if (!others) return;
  wait_ = kThreadCheckSeconds;
  use(free_cores(processors(), *others));
}

void ThreadGovernor::use(int threads) {
  threads_ = std::max(threads, 1);
  set_threads(threads_);
  fewest_ = std::min(fewest_, threads_);
  most_ = std::max(most_, threads_);
}

}  // namespace conserve::assembly
