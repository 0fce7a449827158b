#pragma once
// OUT/profiles.csv, shared by every stage that samples horizontal cuts (coarse/ writes source
// "dem", continuum/ "elastic" and "fpa"). Long format: source,quantity,y_over_h,x_m,value,stderr.
// A stage replaces its own sources' rows and keeps the others', atomically.
#include <string>
#include <vector>

namespace pilelab {

struct ProfileValue {
  std::string source;
  std::string quantity;
  double y_over_h = 0.0;
  double x_m = 0.0;
  double value = 0.0;
  double stderr_ = 0.0;
  bool has_stderr = false;  ///< false: the column is left empty (a model, not a mean)
};

/// Rewrites csv_path with the rows of the sources in `rows` replaced by `rows`. InputError if
/// an existing file has another header.
void write_profile_values(const std::string& csv_path, const std::vector<ProfileValue>& rows);

/// Reads every row; InputError naming the file and line if one is malformed.
std::vector<ProfileValue> read_profile_values(const std::string& csv_path);

/// Points of a horizontal cut across [x_left, x_right]: cell-centred, x_i = x_left +
/// (i + 1/2) (x_right - x_left) / n, so no point sits on the pile's foot.
std::vector<double> profile_points(double x_left, double x_right, int n);

}  // namespace pilelab
