#!/usr/bin/env bash
# The paper study's whole chain on a few small piles: pour three small ensembles standing in for
# the symmetric, asymmetric and monodisperse ones (tests/studies/paper-small-*.toml), keep them as
# the study keeps its members (scripts/study_members.py save), run every later stage with every
# variant (studies/paper/stages.py), rebuild the tables and figures (studies/paper/tables.py),
# and check them (check_paper_tables.py): each ensemble's section, every number finite and
# carrying its standard error, every figure written.
#   paper_study_test.sh SOURCE_DIR PILELAB_BINARY WORK_DIR
set -euo pipefail
source_dir=$1 pilelab=$2 work=$3
rm -rf "$work"
mkdir -p "$work"
export OMP_WAIT_POLICY=passive
for kind in symmetric asymmetric monodisperse; do
  scene=$source_dir/tests/studies/paper-small-$kind.toml
  "$pilelab" run "$scene" -o "$work/pour/$kind" -q -j 1 --no-figures
  /usr/bin/python3 "$source_dir/scripts/study_members.py" save "$work/pour/$kind/members" "$work/study/$kind"
  /usr/bin/python3 "$source_dir/studies/paper/stages.py" "$scene" "$work/study/$kind" "$work/stages/$kind" \
    --pilelab "$pilelab" > "$work/stages-$kind.log"
done
# A member archived as poured replaces a checkpoint of it where it is restored (else the stages
# would pour it again from that checkpoint).
first=$(ls "$work/study/symmetric/data" | head -n 1)
mkdir -p "$work/restore/$first" && echo stale > "$work/restore/$first/checkpoint.h5"
/usr/bin/python3 "$source_dir/scripts/study_members.py" restore "$work/restore" "$work/study/symmetric" > /dev/null
[[ -f $work/restore/$first/dem.h5 && ! -e $work/restore/$first/checkpoint.h5 ]] ||
  { echo "study_members.py restore kept a checkpoint over the archived member $first" >&2; exit 1; }
cp "$source_dir/docs/studies/paper.md" "$work/paper.md"
/usr/bin/python3 "$source_dir/studies/paper/tables.py" "$work/study" --doc "$work/paper.md" --figures "$work/figures"
/usr/bin/python3 "$source_dir/tests/studies/check_paper_tables.py" "$work/paper.md" "$work/figures"
