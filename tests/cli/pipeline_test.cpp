// `pilelab run` end to end on the tiny pile: every stage, every output readable by tools
// pilelab did not write (h5py, meshio), report.json with every documented key; a second run
// skips the unchanged stages.
#include "cli_test_support.h"

using pilelab::test::CliTest;

class Pipeline : public CliTest {};

TEST_F(Pipeline, TinySceneThroughEveryStage) {
  const std::string scene = std::string(PILELAB_SOURCE_DIR) + "/tests/cli/tiny_pipeline.toml";
  const auto first = run("run " + scene + " -o " + path("out") + " -q");
  ASSERT_EQ(first.exit_code, 0) << first.output;
  std::string sections = "dem mesh coarse compare fit";
#ifdef PILELAB_WITH_CONTINUUM
  sections += " continuum";
#endif
  const std::string check = "/usr/bin/python3 " + std::string(PILELAB_SOURCE_DIR) + "/tests/cli/check_outputs.py " +
                            path("out") + " " + PILELAB_SOURCE_DIR + "/docs/FORMAT.md " + sections + " > " +
                            path("check.log") + " 2>&1";
  const int status = std::system(check.c_str());
  std::ifstream log(path("check.log"));
  std::stringstream s;
  s << log.rdbuf();
  EXPECT_EQ(status, 0) << s.str();

  const auto second = run("run " + scene + " -o " + path("out"));
  ASSERT_EQ(second.exit_code, 0) << second.output;
  for (const char* stage : {"dem", "mesh", "coarse", "compare"})
    EXPECT_NE(second.output.find(std::string(stage) + std::string(8 - std::string(stage).size(), ' ') + " skipped"),
              std::string::npos)
        << stage << " was not skipped:\n" << second.output;
}
