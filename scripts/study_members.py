#!/usr/bin/python3
"""Keeps a long ensemble's members in the repository across machines (docs/studies/paper/README.md).

    /usr/bin/python3 scripts/study_members.py save    OUT/members  STUDY_DIR
    /usr/bin/python3 scripts/study_members.py restore OUT/members  STUDY_DIR

save: every poured member (dem.h5 and a report with a dem section) goes to
STUDY_DIR/data/<seed>/ as its archive (scripts/archive_dem.py: the same dem.h5 in 40 % of
the space), with its report.json and scene.toml; every member still pouring (a checkpoint)
goes to STUDY_DIR/checkpoints/<seed>/ (checkpoint.h5, its snapshots file, scene.toml), and a
member once archived loses its stale checkpoint there. Members already saved unchanged are not
copied again.

restore: the reverse, into OUT/members/<seed>/, for `pilelab run` to find: an archived
member counts as poured (its scene, dem.h5 and report are there), a checkpointed one continues
from its checkpoint. Members poured in OUT already are left alone, and so is a checkpoint in
OUT (it may be newer than the archive's), unless the archive holds the member poured.
"""
import filecmp
import json
import os
import shutil
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))


def poured(member):
    report = os.path.join(member, "report.json")
    if not (os.path.exists(os.path.join(member, "dem.h5")) and os.path.exists(report)):
        return False
    try:
        with open(report) as f:
            return "dem" in json.load(f)
    except (OSError, ValueError):
        return False


def copy_if_changed(source, target):
    if os.path.exists(target) and filecmp.cmp(source, target, shallow=False):
        return False
    os.makedirs(os.path.dirname(target), exist_ok=True)
    shutil.copyfile(source, target + ".tmp")
    os.replace(target + ".tmp", target)
    return True


def save(members, study):
    for seed in sorted(os.listdir(members), key=lambda s: (len(s), s)):
        member = os.path.join(members, seed)
        data, checkpoint = os.path.join(study, "data", seed), os.path.join(study, "checkpoints", seed)
        if poured(member):
            same_scene = os.path.exists(os.path.join(data, "scene.toml")) and filecmp.cmp(
                os.path.join(member, "scene.toml"), os.path.join(data, "scene.toml"), shallow=False)
            if not (same_scene and os.path.exists(os.path.join(data, "dem.h5"))):
                os.makedirs(data, exist_ok=True)
                subprocess.run(["/usr/bin/python3", os.path.join(HERE, "archive_dem.py"),
                                os.path.join(member, "dem.h5"), os.path.join(data, "dem.h5")], check=True)
                print(f"member {seed}: poured, archived into {data}")
            for name in ("report.json", "scene.toml"):
                copy_if_changed(os.path.join(member, name), os.path.join(data, name))
            shutil.rmtree(checkpoint, ignore_errors=True)
        elif os.path.exists(os.path.join(member, "checkpoint.h5")):
            changed = False
            for name in ("checkpoint.h5", "checkpoint_snapshots.h5", "scene.toml"):
                if os.path.exists(os.path.join(member, name)):
                    changed |= copy_if_changed(os.path.join(member, name), os.path.join(checkpoint, name))
            if changed:
                print(f"member {seed}: still pouring, checkpoint saved into {checkpoint}")


def restore(members, study):
    for kind in ("data", "checkpoints"):
        root = os.path.join(study, kind)
        if not os.path.isdir(root):
            continue
        for seed in sorted(os.listdir(root)):
            member = os.path.join(members, seed)
            if poured(member):
                continue
            if os.path.exists(os.path.join(member, "checkpoint.h5")):
                # A checkpoint here may be newer than the archive's; a poured member archived
                # since (another machine finished it) supersedes it.
                if kind == "checkpoints":
                    continue
                shutil.rmtree(member)
            os.makedirs(member, exist_ok=True)
            for name in os.listdir(os.path.join(root, seed)):
                shutil.copyfile(os.path.join(root, seed, name), os.path.join(member, name))
            print(f"member {seed}: restored from {kind}")


def main():
    if len(sys.argv) != 4 or sys.argv[1] not in ("save", "restore"):
        sys.exit(__doc__)
    os.makedirs(sys.argv[2], exist_ok=True)
    (save if sys.argv[1] == "save" else restore)(sys.argv[2], sys.argv[3])


if __name__ == "__main__":
    main()
