// Time as the recorder sees it: every wait goes through a Clock, so tests and the simulated backend run
// the same timeouts on simulated time, deterministically.
#pragma once

#include <atomic>

namespace toolinc {

class Clock {
 public:
  virtual ~Clock() = default;
  virtual double now() = 0;  // seconds since an arbitrary origin
  virtual void sleep(double seconds) = 0;
};

// The machine's steady clock.
class SteadyClock : public Clock {
 public:
  double now() override;
  void sleep(double seconds) override;
};

// Simulated time: sleep advances it at once (and, with real_time_factor > 0, also really waits that
// fraction of the time, so a simulated run can be watched or interrupted).
class SimulatedClock : public Clock {
 public:
  explicit SimulatedClock(double real_time_factor = 0.0) : real_time_factor_(real_time_factor) {}
  double now() override { return now_; }
  void sleep(double seconds) override;

 private:
  double now_ = 0.0;
  double real_time_factor_;
};

// Sleeps `seconds` in steps of at most `step`, returning early (false) once `stop` is set.
bool sleep_unless_stopped(Clock& clock, double seconds, const std::atomic<bool>& stop, double step = 0.05);

}  // namespace toolinc
