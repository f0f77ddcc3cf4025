#!/usr/bin/env python3
"""Writes crates/penumbra/tests/data/mitsuba_params.tsv: every parameter of
every plugin that Mitsuba 3's plugin documentation lists and that its
plugin reads from a scene file, one line each:

    kind <TAB> plugin <TAB> parameter <TAB> type as the documentation gives it

`kind` is the folder of Mitsuba's source the plugin is in (`bsdfs`,
`emitters`, `shapes`, `sensors`, `films`, `rfilters`, `samplers`,
`integrators`, `textures`, `spectra`, `media`, `phase`, `volumes`). The
test `crates/penumbra/tests/mitsuba_params.rs` gives each one to Penumbra's
Mitsuba reader.

Source: the `.. pluginparameters::` tables in the documentation comment
at the top of each plugin's `.cpp` file. Left out, because no scene file can
set them:
- nested plugins (rows named "(Nested plugin)");
- objects handed over at run time: tensors, `Bitmap` and `VolumeGrid`
  objects, `Vector2u`/`Point2u` sizes, raw arrays;
- parameters the documentation lists that the plugin never reads from its
  properties (exposed to Python only, e.g. the `eta` a dielectric derives
  from its two indices): the name appears in the plugin's code only in
  `cb->put` lines, and no base class reads it from the properties.

Usage: python3 scripts/mitsuba_params.py MITSUBA3_GIT_DIR [REV] > crates/penumbra/tests/data/mitsuba_params.tsv
where MITSUBA3_GIT_DIR is a clone of https://github.com/mitsuba-renderer/mitsuba3
(a bare one works) and REV the revision to read (default HEAD).

Plain Python, no dependencies besides `git`.
"""

import re
import subprocess
import sys

RUNTIME_TYPES = (
    "tensor",
    "Bitmap object",
    "VolumeGrid object",
    "Vector2u",
    "Point2u",
    "uint32[]",
    "float[]",
)

# Base classes read some parameters for every plugin of a kind (`to_world`
# of shapes, `sample_count` of samplers, the clip planes of cameras).
BASE_PREFIXES = ("src/render/", "src/core/", "include/mitsuba/render/", "include/mitsuba/core/")


def git(repo, *args):
    return subprocess.run(
        ["git", "-C", repo, *args], capture_output=True, text=True, check=True
    ).stdout


def main():
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    repo = sys.argv[1]
    rev = sys.argv[2] if len(sys.argv) > 2 else "HEAD"
    files = git(repo, "ls-tree", "-r", "--name-only", rev, "src", "include").split()

    def show(path):
        return git(repo, "show", f"{rev}:{path}")

    base = "".join(
        show(f)
        for f in files
        if f.startswith(BASE_PREFIXES) and f.endswith((".cpp", ".h"))
    )
    commit = git(repo, "rev-parse", rev).strip()
    seen = set()
    print(f"# Mitsuba 3 plugin parameters, from mitsuba3 {commit} (scripts/mitsuba_params.py)")
    for path in files:
        parts = path.split("/")
        if len(parts) != 3 or parts[0] != "src" or not path.endswith(".cpp"):
            continue
        text = show(path)
        heads = list(re.finditer(r"\(:monosp:`([A-Za-z0-9_]+)`\)", text))
        if not heads:
            continue
        table = r"^\.\. pluginparameters::.*?\n((?:[ \t]*\n|[ \t]+.*\n)+)"
        for m in re.finditer(table, text, re.M):
            before = [h.group(1) for h in heads if h.start() < m.start()]
            if not before:
                continue
            plugin = before[-1]
            code = text[text.find("*/", m.end()):].splitlines()
            for row in re.finditer(r"^ \* - (.+)\n((?:   - .*\n|     .*\n|\s*\n)*)", m.group(1), re.M):
                names, rest = row.group(1), row.group(2).splitlines()
                kind = rest[0].strip()[2:].strip() if rest else ""
                if names.startswith("(") or any(t in kind for t in RUNTIME_TYPES):
                    continue
                for name in (n.strip().strip("`") for n in names.split(",")):
                    quoted = f'"{name}"'
                    read = any(
                        quoted in line
                        and "cb->put" not in line
                        and "name=" not in line
                        and "contains(keys" not in line
                        for line in code
                    ) or re.search(r"props\.[^;]{0,160}" + re.escape(quoted), base)
                    if read and (parts[1], plugin, name) not in seen:
                        seen.add((parts[1], plugin, name))
                        print(f"{parts[1]}\t{plugin}\t{name}\t{kind}")


if __name__ == "__main__":
    main()
