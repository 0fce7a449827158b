#pragma once
// OUT/report.json collects one section per stage ("dem", "coarse", ...). Each stage replaces
// its own section and keeps the others, writing the file atomically.
#include <string>

#include <nlohmann/json.hpp>

namespace pilelab {

void write_report_section(const std::string& report_path, const std::string& section, const nlohmann::json& value);
nlohmann::json read_report(const std::string& report_path);

}  // namespace pilelab
