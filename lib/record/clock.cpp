#include "toolinc/record/clock.hpp"

#include <algorithm>
#include <chrono>
#include <thread>

namespace toolinc {

double SteadyClock::now() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

void SteadyClock::sleep(double seconds) {
  if (seconds > 0) std::this_thread::sleep_for(std::chrono::duration<double>(seconds));
}

void SimulatedClock::sleep(double seconds) {
  if (seconds <= 0) return;
  now_ += seconds;
  if (real_time_factor_ > 0) std::this_thread::sleep_for(std::chrono::duration<double>(seconds * real_time_factor_));
}

bool sleep_unless_stopped(Clock& clock, double seconds, const std::atomic<bool>& stop, double step) {
  const double end = clock.now() + seconds;
  for (double left = seconds; left > 0; left = end - clock.now()) {
    if (stop) return false;
    clock.sleep(std::min(step, left));
  }
  return !stop;
}

}  // namespace toolinc
