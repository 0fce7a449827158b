#include "common/duration_text.h"

#include <cstdio>

namespace pilelab {

std::string duration_text(double seconds) {
  char text[32];
  if (seconds < 120.0)
    std::snprintf(text, sizeof text, "%.0f s", seconds);
  else if (seconds < 7200.0)
    std::snprintf(text, sizeof text, "%.0f min", seconds / 60.0);
  else if (seconds < 172800.0)
    std::snprintf(text, sizeof text, "%.1f h", seconds / 3600.0);
  else
    std::snprintf(text, sizeof text, "%.1f days", seconds / 86400.0);
  return text;
}

}  // namespace pilelab
