#include "common/triangle_vtu.h"

#include <iomanip>
#include <sstream>

#include "common/atomic_file.h"

namespace pilelab {

namespace {
void write_arrays(std::ostringstream& out, const char* tag, const std::vector<VtuField>& fields) {
  if (fields.empty()) return;
  out << "      <" << tag << ">\n";
  for (const auto& f : fields) {
    out << "        <DataArray type=\"Float64\" Name=\"" << f.name << "\"";
    if (f.components != 1) out << " NumberOfComponents=\"" << f.components << "\"";
    out << " format=\"ascii\">\n         ";
    for (double v : f.values) out << ' ' << v;
    out << "\n        </DataArray>\n";
  }
  out << "      </" << tag << ">\n";
}
}  // namespace

void write_triangle_vtu(const std::string& path, const std::vector<std::array<double, 2>>& nodes,
                        const std::vector<std::array<int, 3>>& triangles, const std::vector<VtuField>& point_data,
                        const std::vector<VtuField>& cell_data, std::optional<double> time_s) {
  std::ostringstream out;
  out << std::setprecision(10);
  out << "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\">\n"
      << "  <UnstructuredGrid>\n";
  if (time_s) {  // the grid's field data, before its piece (where ParaView and meshio read it)
    out << std::setprecision(17);  // round trip: ParaView matches times exactly
    out << "    <FieldData>\n      <DataArray type=\"Float64\" Name=\"TimeValue\" NumberOfTuples=\"1\" format=\"ascii\">"
        << *time_s << "</DataArray>\n    </FieldData>\n";
    out << std::setprecision(10);
  }
  out << "    <Piece NumberOfPoints=\"" << nodes.size() << "\" NumberOfCells=\"" << triangles.size() << "\">\n";
  write_arrays(out, "PointData", point_data);
  write_arrays(out, "CellData", cell_data);
  out << "      <Points>\n        <DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n";
  for (const auto& p : nodes) out << "          " << p[0] << ' ' << p[1] << " 0\n";
  out << "        </DataArray>\n      </Points>\n      <Cells>\n"
      << "        <DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n";
  for (const auto& t : triangles) out << "          " << t[0] << ' ' << t[1] << ' ' << t[2] << '\n';
  out << "        </DataArray>\n        <DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n         ";
  for (std::size_t c = 0; c < triangles.size(); ++c) out << ' ' << 3 * (c + 1);
  out << "\n        </DataArray>\n        <DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n         ";
  for (std::size_t c = 0; c < triangles.size(); ++c) out << " 5";
  out << "\n        </DataArray>\n      </Cells>\n    </Piece>\n  </UnstructuredGrid>\n</VTKFile>\n";
  write_text_atomically(path, out.str());
}

}  // namespace pilelab
