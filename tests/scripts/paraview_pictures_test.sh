#!/usr/bin/env bash
# scripts/paraview_pictures.py on a run's outputs: both pictures are written, full size and not
# blank; docs/FORMAT.md's pvpython recipe runs; on a full disk, exit 2 with the previous picture
# kept. Skipped (exit 77) where ParaView's pvpython or xvfb-run is not installed.
#   bash tests/scripts/paraview_pictures_test.sh REPO OUT
set -euo pipefail
repo=$1 out=$2
if ! command -v pvpython >/dev/null || ! command -v xvfb-run >/dev/null; then
  echo "pvpython or xvfb-run is missing (Debian: python3-paraview, xvfb): skipped"
  exit 77
fi
rm -f "$out"/figures/paraview_*.png
# The virtual display sometimes refuses pvpython's connection on a loaded machine ("bad X server
# connection"): try three times; if the display never works, that is the machine's, not ours.
log=$(mktemp)
for attempt in 1 2 3; do
  if xvfb-run -a -s "-screen 0 1920x1080x24" pvpython "$repo/scripts/paraview_pictures.py" "$out" > "$log" 2>&1; then
    break
  fi
  if ! grep -q "bad X server connection" "$log"; then
    cat "$log"
    exit 1
  fi
  if [ "$attempt" = 3 ]; then
    echo "the virtual X display refused pvpython three times: skipped"
    exit 77
  fi
  sleep 2
done
grep -v "0x" "$log" | grep wrote
/usr/bin/python3 - "$out" <<'PY'
import sys
import matplotlib.image as image
for name in ("paraview_force_chains.png", "paraview_stress.png"):
    a = image.imread(f"{sys.argv[1]}/figures/{name}")[..., :3]
    assert a.shape[0] >= 600 and a.shape[1] >= 1500, f"{name}: {a.shape}"
    # A picture, not a blank: the white background and at least two other colours in quantity.
    assert a.std() > 0.05, f"{name} is nearly uniform (std {a.std():.3f})"
    print(name, a.shape, f"std {a.std():.3f}")
PY
# The force-chain recipe of docs/FORMAT.md, as a user would paste it (OUT and the frame replaced):
# it must run under pvpython and write its picture (fed the file directly, Tube crashed 5.11).
recipe=$(mktemp -d)
last_contacts=$(ls "$out"/contacts_*.vtu | tail -1)
awk '/^# pvpython recipe: force chains/{on=1} on&&/^```/{exit} on' "$repo/docs/FORMAT.md" |
  sed "s|OUT/contacts_00009.vtu|$last_contacts|; s|force_chains.png|$recipe/force_chains.png|" > "$recipe/recipe.py"
grep -q "Tube(" "$recipe/recipe.py" || { echo "the recipe was not found in docs/FORMAT.md"; exit 1; }
# (xvfb-run itself may fail to clean up after pvpython has written the picture: the picture decides.)
for attempt in 1 2 3; do
  xvfb-run -a -s "-screen 0 1920x1080x24" pvpython "$recipe/recipe.py" > "$log" 2>&1 || true
  [ -s "$recipe/force_chains.png" ] && break
  if ! grep -q "bad X server connection\|xvfb-run: error" "$log" || [ "$attempt" = 3 ]; then cat "$log"; echo "the docs' recipe failed"; exit 1; fi
  sleep 2
done
[ -s "$recipe/force_chains.png" ] || { echo "the docs' recipe wrote no picture"; exit 1; }
echo "docs/FORMAT.md's force-chain recipe: ran, $(stat -c %s "$recipe/force_chains.png") bytes"
rm -rf "$recipe"

# On a full disk (a 64 KiB tmpfs as OUT/figures, where root may mount one): exit 2 naming the
# picture, no traceback, no temporary file, and the picture already there kept whole.
disk=$(mktemp -d)
if mount -t tmpfs -o size=64k tmpfs "$disk" 2>/dev/null; then
  trap 'umount "$disk"; rm -rf "$disk"' EXIT
  full=$(mktemp -d)
  cp "$out"/report.json "$out"/*.pvd "$out"/*.vtu "$out"/*.h5 "$full"/ 2>/dev/null || true
  ln -s "$disk" "$full/figures"
  head -c 20000 "$out/figures/paraview_stress.png" > "$disk/paraview_stress.png"  # "the previous picture"
  cp "$disk/paraview_stress.png" "$full.previous"
  for attempt in 1 2 3; do
    set +e
    xvfb-run -a -s "-screen 0 1920x1080x24" pvpython "$repo/scripts/paraview_pictures.py" "$full" > "$log" 2>&1
    code=$?
    set -e
    grep -q "bad X server connection\|xvfb-run: error" "$log" || break
    sleep 2
  done
  if grep -q "bad X server connection\|xvfb-run: error" "$log"; then
    echo "the virtual X display failed: the full-disk case is skipped"
  else
    [ "$code" = 2 ] || { cat "$log"; echo "full disk: exit $code, expected 2"; exit 1; }
    grep -q "cannot write" "$log" || { cat "$log"; exit 1; }
    ! grep -q Traceback "$log" || { cat "$log"; exit 1; }
    ! ls "$disk" | grep -q "\.tmp\." || { ls "$disk"; echo "a temporary file was left"; exit 1; }
    cmp -s "$disk/paraview_stress.png" "$full.previous" || { echo "the previous picture was replaced"; exit 1; }
    echo "full disk: exit 2, $(grep 'cannot write' "$log" | head -1)"
  fi
  rm -rf "$full" "$full.previous"
fi
