// checkpoint.h5: a restart's state through the checkpoint reader, for the scene the seed
// checkpoints were written for (fuzz/seed_scene.toml, a pile of 8 grains). The snapshots a
// checkpoint keeps beside it (CHECKPOINT_snapshots.h5) are the seed run's, so that inputs that
// pass the checkpoint's own checks go on to restore them.
#include <filesystem>

#include "common/scene_reader.h"
#include "dem/checkpoint.h"
#include "dem/dem_scene.h"
#include "fuzz/fuzz_target.h"

using namespace pilelab;

namespace {
const std::string& scene_text() {
  static const std::string text = SceneReader::from_file(PILELAB_FUZZ_DIR "/seed_scene.toml").text();
  return text;
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const fuzz::InputFile file(data, size, ".h5");
  const std::string snapshots = file.path().substr(0, file.path().size() - 3) + "_snapshots.h5";
  std::filesystem::copy_file(PILELAB_FUZZ_DIR "/checkpoint_snapshots.h5", snapshots,
                             std::filesystem::copy_options::overwrite_existing);
  SceneReader reader(scene_text(), "seed_scene.toml");
  dem::PileProtocol protocol(dem::read_dem_scene(reader), "seed_scene.toml");
  dem::RunCounters counters;
  fuzz::expect_clean_refusal("checkpoint", [&] { dem::read_checkpoint(file.path(), scene_text(), protocol, counters); });
  std::filesystem::remove(snapshots);
  return 0;
}
