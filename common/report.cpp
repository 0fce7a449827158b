#include "common/report.h"

#include <filesystem>

#include "common/atomic_file.h"
#include "common/error.h"

namespace pilelab {

nlohmann::json read_report(const std::string& report_path) {
  if (!std::filesystem::exists(report_path)) return nlohmann::json::object();
  try {
    return nlohmann::json::parse(read_text_file(report_path));
  } catch (const nlohmann::json::exception& e) {
    throw InputError(report_path + ": not valid JSON: " + e.what());
  }
}

void write_report_section(const std::string& report_path, const std::string& section, const nlohmann::json& value) {
  nlohmann::json report = read_report(report_path);
  report[section] = value;
  write_text_atomically(report_path, report.dump(2) + "\n");
}

}  // namespace pilelab
