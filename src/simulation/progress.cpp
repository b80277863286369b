#include "simulation/progress.hpp"

#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>

namespace conserve::simulation {

std::int64_t steps_left(double time, double end, double dt, std::int64_t taken, std::int64_t max_steps, bool last) {
  if (last) return 0;
  constexpr double kMost = 4611686018427387904.0;  // 2^62, exact in a double
  const double by_time = std::clamp(std::ceil((end - time) / dt - 1e-6), 0.0, kMost);
  return std::max<std::int64_t>(1, std::min(static_cast<std::int64_t>(by_time), max_steps - taken));
}

ProgressLine::ProgressLine(std::FILE* out, int every)
    : out_(out),
      every_(every),
      tty_(out && isatty(fileno(out))),
      start_(std::chrono::steady_clock::now()),
      last_(start_) {}

double ProgressLine::elapsed() const {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
}

void ProgressLine::update(const ProgressPoint& p) {
  if (!out_) return;
  const auto now = std::chrono::steady_clock::now();
  const bool due = every_ > 0 ? p.step % every_ == 0 : now - last_ >= std::chrono::seconds(1);
  if (!due && !p.last) return;
  last_ = now;
  const double t = elapsed();
  const double eta = p.last ? 0.0 : (p.fraction > 0.0 ? t * (1.0 - p.fraction) / p.fraction : 0.0);
  fmt::print(out_, "{}step {}/{}  t = {:.4g} s  {:.0f}%  |ΔE|/E_ref = {:.2e}  Newton {}  elapsed {:.1f} s  ETA {:.1f} s{}",
             tty_ ? "\r" : "", p.step, p.expected_steps, p.time, 100.0 * p.fraction, p.energy_drift,
             p.newton_iterations, t, eta, tty_ ? "  " : "\n");
  std::fflush(out_);
  printed_ = true;
}

void ProgressLine::finish() {
  if (out_ && tty_ && printed_) fmt::print(out_, "\n");
}

}  // namespace conserve::simulation
