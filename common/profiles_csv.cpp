#include "common/profiles_csv.h"

#include <cstdio>
#include <filesystem>
#include <set>
#include <sstream>

#include "common/atomic_file.h"
#include "common/error.h"

namespace pilelab {

namespace {
const char* const header = "source,quantity,y_over_h,x_m,value,stderr";
}

void write_profile_values(const std::string& csv_path, const std::vector<ProfileValue>& rows) {
  std::set<std::string> replaced;
  for (const auto& r : rows) replaced.insert(r.source);
  std::ostringstream out;
  out << header << "\n";
  if (std::filesystem::exists(csv_path)) {
    std::istringstream in(read_text_file(csv_path));
    std::string line;
    std::getline(in, line);
    if (line != header)
      throw InputError(csv_path + ": unexpected header \"" + line + "\" (expected \"" + header + "\")");
    while (std::getline(in, line))
      if (!line.empty() && !replaced.count(line.substr(0, line.find(',')))) out << line << "\n";
  }
  char buf[512];
  for (const auto& r : rows) {
    if (r.has_stderr)
      std::snprintf(buf, sizeof buf, "%s,%s,%.6g,%.9g,%.9g,%.9g\n", r.source.c_str(), r.quantity.c_str(), r.y_over_h,
                    r.x_m, r.value, r.stderr_);
    else
      std::snprintf(buf, sizeof buf, "%s,%s,%.6g,%.9g,%.9g,\n", r.source.c_str(), r.quantity.c_str(), r.y_over_h,
                    r.x_m, r.value);
    out << buf;
  }
  write_text_atomically(csv_path, out.str());
}

std::vector<ProfileValue> read_profile_values(const std::string& csv_path) {
  std::istringstream in(read_text_file(csv_path));
  std::string line;
  std::getline(in, line);
  if (line != header)
    throw InputError(csv_path + ": unexpected header \"" + line + "\" (expected \"" + header + "\")");
  std::vector<ProfileValue> rows;
  int number = 1;
  while (std::getline(in, line)) {
    ++number;
    if (line.empty()) continue;
    std::vector<std::string> cells;
    std::stringstream s(line);
    std::string cell;
    while (std::getline(s, cell, ',')) cells.push_back(cell);
    if (cells.size() == 5) cells.emplace_back();
    try {
      if (cells.size() != 6) throw std::invalid_argument("columns");
      ProfileValue r;
      r.source = cells[0];
      r.quantity = cells[1];
      r.y_over_h = std::stod(cells[2]);
      r.x_m = std::stod(cells[3]);
      r.value = std::stod(cells[4]);
      r.has_stderr = !cells[5].empty();
      if (r.has_stderr) r.stderr_ = std::stod(cells[5]);
      rows.push_back(r);
    } catch (const std::exception&) {
      throw InputError(csv_path + ": line " + std::to_string(number) +
                       " is not source,quantity,y_over_h,x_m,value,stderr with numbers");
    }
  }
  return rows;
}

std::vector<double> profile_points(double x_left, double x_right, int n) {
  std::vector<double> x(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) x[i] = x_left + (i + 0.5) * (x_right - x_left) / n;
  return x;
}

}  // namespace pilelab
