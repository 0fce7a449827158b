#pragma once
// A span of (wall-clock or core) time as a person reads it, for progress lines and estimates.
#include <string>

namespace pilelab {

/// Seconds below 2 minutes, minutes below 2 hours, hours below 2 days, else days.
std::string duration_text(double seconds);

}  // namespace pilelab
