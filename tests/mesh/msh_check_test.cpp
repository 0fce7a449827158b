// mesh/msh_check: the structural check that keeps damaged mesh files away from gmsh's reader
// (which crashed on an element naming an undefined node, found by fuzzing). A well-formed file
// of either ASCII format passes; each kind of damage is refused with the file, the line and the
// section named.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <unistd.h>

#include "common/error.h"
#include "mesh/msh_check.h"

using namespace pilelab;

namespace {

// Two triangles on the unit square, in MSH 4.1: four nodes in one block, two elements.
const char* square_41 =
    "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n"
    "$Nodes\n1 4 1 4\n2 1 0 4\n1\n2\n3\n4\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n$EndNodes\n"
    "$Elements\n1 2 1 2\n2 1 2 2\n1 1 2 3\n2 1 3 4\n$EndElements\n";

// The same in MSH 2.2 (each element: tag, type, number of tags, tags, nodes).
const char* square_22 =
    "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n"
    "$Nodes\n4\n1 0 0 0\n2 1 0 0\n3 1 1 0\n4 0 1 0\n$EndNodes\n"
    "$Elements\n2\n1 2 2 100 1 1 2 3\n2 2 2 100 1 1 3 4\n$EndElements\n";

std::string write(const std::string& name, const std::string& text) {
  const auto path = std::filesystem::temp_directory_path() / (name + "_" + std::to_string(::getpid()) + ".msh");
  std::ofstream(path) << text;
  return path.string();
}

std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return text.replace(at, from.size(), to);
}

// The check's message for a text, or "" if it passes.
std::string refusal(const std::string& text) {
  const std::string path = write("msh_check", text);
  try {
    mesh::check_msh_file(path);
  } catch (const InputError& e) {
    std::filesystem::remove(path);
    return e.what();
  }
  std::filesystem::remove(path);
  return "";
}

}  // namespace

TEST(MshCheck, WellFormedFilesOfBothFormatsPass) {
  EXPECT_EQ(refusal(square_41), "");
  EXPECT_EQ(refusal(square_22), "");
}

TEST(MshCheck, AnElementNamingAnUndefinedNodeIsRefusedWithItsLine) {
  const std::string m = refusal(replaced(square_41, "2 1 3 4\n$EndElements", "2 1 3 1007801056276039642\n$EndElements"));
  EXPECT_NE(m.find("line 20"), std::string::npos) << m;
  EXPECT_NE(m.find("node 1007801056276039642, which $Nodes does not define"), std::string::npos) << m;
  const std::string m22 = refusal(replaced(square_22, "1 3 4\n$EndElements", "1 3 5\n$EndElements"));
  EXPECT_NE(m22.find("node 5"), std::string::npos) << m22;
}

TEST(MshCheck, CountsThatDisagreeWithTheBlocksAreRefused) {
  EXPECT_NE(refusal(replaced(square_41, "$Nodes\n1 4 1 4", "$Nodes\n1 5 1 5")).find("the blocks hold 4 nodes, the header says 5"),
            std::string::npos);
  EXPECT_NE(refusal(replaced(square_41, "$Elements\n1 2 1 2", "$Elements\n1 3 1 3")).find("the blocks hold 2 elements"),
            std::string::npos);
}

TEST(MshCheck, TagsOutsideTheDeclaredRangeOrDefinedTwiceAreRefused) {
  EXPECT_NE(refusal(replaced(square_41, "1\n2\n3\n4\n0 0 0", "1\n2\n3\n9\n0 0 0")).find("node tag 9 is out of range"),
            std::string::npos);
  EXPECT_NE(refusal(replaced(square_41, "1\n2\n3\n4\n0 0 0", "1\n2\n3\n3\n0 0 0")).find("node tag 3 is defined twice"),
            std::string::npos);
}

TEST(MshCheck, NonNumbersUnknownElementsBinaryAndTruncatedFilesAreRefused) {
  EXPECT_NE(refusal(replaced(square_41, "1 1 0\n", "1 nan 0\n")).find("not a finite number"), std::string::npos);
  EXPECT_NE(refusal(replaced(square_41, "2 1 2 2\n", "2 1 99 2\n")).find("element type 99"), std::string::npos);
  EXPECT_NE(refusal(replaced(square_41, "4.1 0 8", "4.1 1 8")).find("binary"), std::string::npos);
  EXPECT_NE(refusal(replaced(square_41, "4.1 0 8", "3.0 0 8")).find("version 3.0"), std::string::npos);
  const std::string text = square_41;
  EXPECT_NE(refusal(text.substr(0, text.size() / 2)).find("ends early"), std::string::npos);
  EXPECT_NE(refusal("").find("ends early"), std::string::npos);
}

// gmsh 4.8 crashed on a physical name of dimension 4 (found by fuzzing): names are checked.
TEST(MshCheck, PhysicalNamesOfABadDimensionOrWithoutQuotesAreRefused) {
  const std::string names = "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$PhysicalNames\n2\n1 1 \"BoundaryID:1\"\n";
  const std::string body = std::string(square_41).substr(std::string(square_41).find("$Nodes"));
  EXPECT_EQ(refusal(names + "2 100 \"Material ID\"\n$EndPhysicalNames\n" + body), "") << "a name with a space passes";
  const std::string m = refusal(names + "4 100 \"MaterialID:0\"\n$EndPhysicalNames\n" + body);
  EXPECT_NE(m.find("line 7"), std::string::npos) << m;
  EXPECT_NE(m.find("$PhysicalNames: dimension 4 is out of range [0, 3]"), std::string::npos) << m;
  EXPECT_NE(refusal(names + "2 100 MaterialID\n$EndPhysicalNames\n" + body).find("a name in double quotes expected"),
            std::string::npos);
}
