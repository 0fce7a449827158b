#!/usr/bin/env bash
# AddressSanitizer and UndefinedBehaviorSanitizer (the `sanitize` preset, build-sanitize/, every
# module but deal.II's; docs/RELIABILITY.md):
#   bash scripts/sanitize.sh        the whole suite (on 2 cores about 17 min of build, 10 of tests)
#   bash scripts/sanitize.sh --ci   the reduced set the test command runs: the DEM's step, contacts,
#                                   integrators and time-step bound, the file layer, and every
#                                   reader on its fuzz corpus (about 6 min of build, 1 of tests)
set -euo pipefail
cd "$(dirname "$0")/.."
cmake --preset sanitize > /dev/null
if [[ ${1:-} == --ci ]]; then
  targets=(world_test collision_test integrator_test contact_law_test dem_file_test time_step_test
           hdf5_file_test atomic_file_test fields_attributes_test msh_check_test
           fuzz_scene_replay fuzz_mesh_replay fuzz_dem_file_replay fuzz_fields_replay fuzz_checkpoint_replay)
  cmake --build --preset sanitize --target "${targets[@]}"
  ctest --preset sanitize -R '^(World|Collision|Integrator|ContactLaw|DemFile|TimeStep|H5File|AtomicFile|FieldsAttributes|MshCheck|fuzz_replay)'
else
  cmake --build --preset sanitize
  ctest --preset sanitize
fi
