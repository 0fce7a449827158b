#!/usr/bin/env bash
# Pours the members of the paper study that are not poured yet, one member per core, and keeps
# them in the repository (docs/studies/paper/README.md). Resumable: members archived in
# docs/studies/paper/<ensemble>/data count as poured, checkpointed ones continue.
#
#   bash studies/paper/pour.sh [ENSEMBLE...]     ENSEMBLE: symmetric, asymmetric, monodisperse,
#                                                symmetric-paper-step, asymmetric-travel-0.5
#
# The ensembles run one after the other, in the order given (all five by default). For each:
# restore the archive into out/paper-<ensemble>/members, `pilelab run` the scene with -P
# $PROCESSES -j 1 (which pours the missing members and then runs the later stages on all of
# them), save the members back into the archive. Commit the archive afterwards.
# PILELAB names the binary (default: a copy of build/apps/pilelab, so that a rebuild cannot
# replace a running pour's executable); PROCESSES defaults to the number of cores.
set -euo pipefail
cd "$(dirname "$0")/../.."
processes=${PROCESSES:-$(nproc)}
if [[ -z ${PILELAB:-} ]]; then
  PILELAB=out/pilelab-pour
  mkdir -p out
  cp build/apps/pilelab "$PILELAB.tmp" && mv "$PILELAB.tmp" "$PILELAB"
fi
ensembles=("$@")
((${#ensembles[@]})) || ensembles=(symmetric asymmetric monodisperse symmetric-paper-step asymmetric-travel-0.5)
export OMP_WAIT_POLICY=passive
for e in "${ensembles[@]}"; do
  scene=scenes/paper-$e.toml study=docs/studies/paper/$e out=out/paper-$e
  [[ -f $scene ]] || { echo "pour.sh: no scene $scene" >&2; exit 2; }
  /usr/bin/python3 scripts/study_members.py restore "$out/members" "$study"
  status=0
  # --allow-unsettled: the study measures every pile; an unfit one is recorded in the status.
  "$PILELAB" run "$scene" -o "$out" -P "$processes" -j 1 --allow-unsettled || status=$?
  /usr/bin/python3 scripts/study_members.py save "$out/members" "$study"
  ((status == 0)) || exit "$status"
done
