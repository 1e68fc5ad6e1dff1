// Wall-clock seconds spent in each named stage of the time step.
#pragma once

#include <chrono>
#include <map>
#include <string>

namespace efsi {

class StageTimers {
  public:
    template <class F>
    void time(const std::string& stage, F&& f) {
        const auto t0 = std::chrono::steady_clock::now();
        f();
        seconds_[stage] +=
            std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    }
    const std::map<std::string, double>& seconds() const { return seconds_; }

  private:
    std::map<std::string, double> seconds_;
};

} // namespace efsi
