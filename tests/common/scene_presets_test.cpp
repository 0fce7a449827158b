// Named presets ([scene] preset): they fill in only what the scene leaves out, only in the
// tables the scene has, and an unknown name is refused with the names that exist.
#include <gtest/gtest.h>

#include "common/error.h"
#include "common/scene_presets.h"
#include "common/scene_reader.h"

using namespace pilelab;

TEST(ScenePresets, FillOnlyWhatTheSceneLeavesOut) {
  SceneReader r("[scene]\npreset = \"fast\"\n[dem]\ngrain_count = 40\n[dem.settle]\nkinetic_energy_per_grain_J = 2e-7\n",
                "scene.toml");
  // The preset's key where the scene has none; the scene's own where it has one.
  EXPECT_EQ(r.get_double("dem.integrator.time_step_fraction", 0.8, Range::positive()), 0.95);
  EXPECT_EQ(r.get_double("dem.settle.kinetic_energy_per_grain_J", 1e-7, Range::positive()), 2e-7);
  // No stage is added: the scene has no [continuum], so the preset's continuum keys stay out.
  EXPECT_FALSE(r.has("continuum"));
  EXPECT_TRUE(r.table_text("continuum").empty());
}

TEST(ScenePresets, EveryPresetIsValidTomlOfKnownTables) {
  for (const auto& [name, text] : scene_presets()) {
    SceneReader all("[scene]\npreset = \"" + name + "\"\n[dem]\n[continuum]\n", "scene.toml");
    EXPECT_TRUE(all.has("dem.integrator.scheme")) << name;
    EXPECT_TRUE(all.has("continuum.elastic.degree")) << name;
  }
}

TEST(ScenePresets, AnUnknownNameIsRefusedWithTheKnownOnes) {
  try {
    SceneReader("[scene]\npreset = \"quick\"\n", "scene.toml");
    FAIL() << "an unknown preset was accepted";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("scene.preset"), std::string::npos) << m;
    EXPECT_NE(m.find("\"fast\""), std::string::npos) << m;
  }
}
