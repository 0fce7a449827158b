#pragma once
// ParaView output: ASCII VTU files (XML UnstructuredGrid) of the grains and of the contact
// network, and a .pvd collection that lists them by time. Every file is written atomically.
// Arrays, units and conventions: docs/FORMAT.md, section "dem.pvd / grains_*.vtu / contacts_*.vtu".
#include <cstdint>
#include <string>
#include <vector>

#include "dem/world.h"

namespace pilelab::dem {

/// Discs are drawn as regular polygons with this many corners.
constexpr int disc_outline_corners = 24;

/// One VTK_POLYGON cell per active grain (by body index), outlines placed from each body's
/// position and angle. Cell data: body, is_wall, velocity, angular_velocity, contact_force,
/// contact_count, speed, angle, area, radius, stress, pressure. Field data: TimeValue, TIME.
void write_grains_vtu(const std::string& path, const World& world);

/// The walls (the plate, the funnel, fixed base grains) as write_grains_vtu writes grains, so that
/// they are a block of their own in ParaView (is_wall 1, stress and pressure 0).
void write_walls_vtu(const std::string& path, const World& world);

/// One VTK_LINE cell per contact, from the centroid of a (for a wall: the contact point) to the
/// centroid of b. Cell data: body_a, body_b, normal_force, tangential_force, force, overlap_area,
/// chord. A world without contacts gives a valid file with no cells.
void write_contacts_vtu(const std::string& path, const World& world);

/// A .pvd collection of VTU files by time. Call write() after adding each frame's parts. The
/// first write() writes the file whole (atomically); later ones append the new entries in place,
/// with the closing tags, in one write at the old closing tags' offset, so that a long pour
/// writes each entry once (rewriting the whole file each frame wrote 8.1 GB to keep 1.2 GB over
/// 8138 frames) and a killed run still leaves a valid .pvd of the frames written so far. A file
/// changed behind the series' back (another size than it wrote) is written whole again.
class PvdSeries {
 public:
  explicit PvdSeries(std::string path);
  /// vtu_file_relative is relative to the directory of the .pvd; part tells apart files of the
  /// same time (e.g. 0 grains, 1 contacts), and name is the block's name in ParaView.
  void add(double time, const std::string& vtu_file_relative, int part, const std::string& name = "");
  void write();
  std::size_t size() const { return entries_.size(); }
  const std::string& path() const { return path_; }

 private:
  struct Entry {
    double time;
    std::string file;
    int part;
    std::string name;
  };
  static std::string entry_text(const Entry& e);
  void write_whole();
  std::string path_;
  std::vector<Entry> entries_;
  std::size_t entries_written_ = 0;   ///< entries in the file
  std::uintmax_t bytes_written_ = 0;  ///< the file's size after the last write (0: never written)
};

}  // namespace pilelab::dem
