// Wall-clock seconds spent in each named stage of the time step.
#pragma once

#include <chrono>
#include <map>
#include <string>

namespace efsi {

/// A stage timed inside another (a body's surface velocity inside the bodies' tensor stage)
/// counts for itself only: the outer stage gets its own time less the inner one, so the
/// stages add up to the step.
class StageTimers {
  public:
    template <class F>
    void time(const std::string& stage, F&& f) {
        const double outer_nested = nested_;
        nested_ = 0;
        const auto t0 = std::chrono::steady_clock::now();
        f();
        const double total =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        seconds_[stage] += total - nested_;
        nested_ = outer_nested + total;
    }
    const std::map<std::string, double>& seconds() const { return seconds_; }

  private:
    std::map<std::string, double> seconds_;
    double nested_ = 0; ///< seconds of the stages timed inside the one running now
};

} // namespace efsi
