#pragma once
// A triangulation with named scalar and vector fields as a VTK XML unstructured grid (.vtu, ASCII), for
// ParaView and meshio. Written atomically.
#include <array>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace pilelab {

struct VtuField {
  std::string name;
  std::vector<double> values;  ///< components per node (point data) or per triangle (cell data)
  int components = 1;          ///< 3 for a vector (x, y, 0), which ParaView can glyph or warp by
};

/// time_s, when given, is written as the field TimeValue, which ParaView shows as the data's time.
void write_triangle_vtu(const std::string& path, const std::vector<std::array<double, 2>>& nodes,
                        const std::vector<std::array<int, 3>>& triangles, const std::vector<VtuField>& point_data,
                        const std::vector<VtuField>& cell_data = {}, std::optional<double> time_s = std::nullopt);

}  // namespace pilelab
