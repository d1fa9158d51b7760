// Wall-clock timing of named stages, appended in the order they ran.
#pragma once
#include <chrono>
#include <string>
#include <utility>
#include <vector>

namespace voxlux {

using StageTimes = std::vector<std::pair<std::string, double>>;

class StageClock {
public:
    explicit StageClock(StageTimes& out) : out_(out) {}
    template <typename F>
    auto operator()(const std::string& stage, F&& work) {
        auto start = std::chrono::steady_clock::now();
        auto finish = [&] {
            out_.emplace_back(stage, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
        };
        if constexpr (std::is_void_v<decltype(work())>) {
            work();
            finish();
        } else {
            auto result = work();
            finish();
            return result;
        }
    }

private:
    StageTimes& out_;
};

}  // namespace voxlux
