#include "simulation/progress.hpp"

#include <fmt/format.h>
#include <unistd.h>

namespace conserve::simulation {

ProgressLine::ProgressLine(std::FILE* out, int total_steps, int every)
    : out_(out),
      total_(total_steps),
      every_(every),
      tty_(out && isatty(fileno(out))),
      start_(std::chrono::steady_clock::now()),
      last_(start_) {}

double ProgressLine::elapsed() const {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
}

void ProgressLine::update(int step, double time, double energy_drift, int newton_iterations) {
  if (!out_) return;
  const auto now = std::chrono::steady_clock::now();
  const bool due = every_ > 0 ? step % every_ == 0 : now - last_ >= std::chrono::seconds(1);
  if (!due && step != total_) return;
  last_ = now;
  const double t = elapsed();
  const double eta = step > 0 ? t * (total_ - step) / step : 0.0;
  fmt::print(out_, "{}step {}/{}  t = {:.4g} s  |ΔE|/E = {:.2e}  Newton {}  elapsed {:.1f} s  ETA {:.1f} s{}",
             tty_ ? "\r" : "", step, total_, time, energy_drift, newton_iterations, t, eta, tty_ ? "  " : "\n");
  std::fflush(out_);
  printed_ = true;
}

void ProgressLine::finish() {
  if (out_ && tty_ && printed_) fmt::print(out_, "\n");
}

}  // namespace conserve::simulation
