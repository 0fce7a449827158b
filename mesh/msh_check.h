#pragma once
// A structural check of a gmsh mesh file before gmsh's own reader sees it. gmsh 4.8 trusts the
// file: an element naming a node tag the file never defines made it read far outside its node
// table and crash (found by fuzz/fuzz_mesh.cpp). This check reads the ASCII formats pilelab and
// most tools write (MSH 4.1 and 2.2) far enough to refuse such files with InputError, naming the
// file, the section and the line: counts that do not match, node tags outside the declared range
// or defined twice, elements of an unknown type, elements naming undefined nodes, non-numbers.
#include <string>

namespace pilelab::mesh {

/// Throws InputError if path is not a well-formed ASCII MSH 4.1 or 2.2 file; binary files and
/// other versions are refused too (pilelab writes ASCII 4.1; gmsh converts others with
/// `gmsh -save -format msh41 FILE`).
void check_msh_file(const std::string& path);

}  // namespace pilelab::mesh
