#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""The SPDX convention (README, "Layout"): every source, build and script file of
vrsph names its licence in its first lines, `SPDX-License-Identifier: BSD-3-Clause`.

usage: check_spdx.py SOURCE_DIR"""
import pathlib
import sys

ROOT = pathlib.Path(sys.argv[1])
FOLDERS = ("include", "src", "apps", "python", "tests", "fuzz", "bench", "scripts", "cmake", "share", "examples")
SUFFIXES = {".cpp", ".hpp", ".h", ".py", ".pyi", ".cmake", ".sh", ".in", ".txt"}
TAG = "SPDX-License-Identifier: BSD-3-Clause"


def wanted(path):
    if path.name == "CMakeLists.txt":
        return True
    if path.suffix not in SUFFIXES or path.name.endswith(".txt"):
        return False
    return not any(part in ("corpus", "fixtures", "vtk", "gmsh", "__pycache__") for part in path.parts)


missing = []
files = [ROOT / "setup.py"] + [p for f in FOLDERS for p in sorted((ROOT / f).rglob("*")) if p.is_file() and wanted(p)]
for path in files:
    head = path.read_text(encoding="utf-8", errors="replace").splitlines()[:3]
    if not any(TAG in line for line in head):
        missing.append(str(path.relative_to(ROOT)))
if missing:
    print(f"{len(missing)} of {len(files)} files lack '{TAG}' in their first three lines:")
    print("\n".join(missing))
    sys.exit(1)
print(f"all {len(files)} files carry the SPDX header")
