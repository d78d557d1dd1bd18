#pragma once
// What a long-running library call may report back: log lines and progress.
// The library never writes to stdout/stderr itself; tools decide where it goes.

#include <functional>
#include <string>

namespace bpm {

enum class LogLevel { Debug, Info, Warning };

struct Context {
    // Called with human-readable lines (no trailing newline). May be empty.
    std::function<void(LogLevel, const std::string&)> log;
    // Called with a fraction in [0,1] and a short description of the stage.
    // Returning false asks the call to stop; it then throws bpm::Cancelled.
    std::function<bool(double, const std::string&)> progress;

    void info(const std::string& message) const {
        if (log) log(LogLevel::Info, message);
    }
    void warn(const std::string& message) const {
        if (log) log(LogLevel::Warning, message);
    }
    void debug(const std::string& message) const {
        if (log) log(LogLevel::Debug, message);
    }
    // Reports progress; throws bpm::Cancelled if the callback says stop.
    void report(double fraction, const std::string& stage) const;
};

}  // namespace bpm
