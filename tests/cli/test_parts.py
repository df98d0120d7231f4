#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""The CLI in a build with or without each optional part (issue 36): `--version` lists the
parts; a command that needs a part this build lacks exits 2 naming the part and the CMake
option; one with all its parts works. Runs in every build (the full one: every command works).

usage: test_parts.py VRSPH"""
import base64
import json
import os
import re
import struct
import subprocess
import sys
import tempfile
import unittest
import zlib

VRSPH = sys.argv.pop(1) if len(sys.argv) > 1 else "vrsph"

CUBE_OFF = """OFF
8 12 0
0 0 0
1 0 0
1 1 0
0 1 0
0 0 1
1 0 1
1 1 1
0 1 1
3 0 2 1
3 0 3 2
3 4 5 6
3 4 6 7
3 0 1 5
3 0 5 4
3 2 3 7
3 2 7 6
3 1 2 6
3 1 6 5
3 3 0 4
3 3 4 7
"""


def run(*args, cwd=None):
    return subprocess.run([VRSPH, *args], capture_output=True, text=True, timeout=240, cwd=cwd)


def parts():
    out = run("--version").stdout
    built = next(l for l in out.splitlines() if l.startswith("built with:")).split(":")[1].split()
    return set(built) - {"none"}


class Parts(unittest.TestCase):
    def setUp(self):
        self.built = parts()
        self.tmp = tempfile.TemporaryDirectory()
        self.addCleanup(self.tmp.cleanup)

    def file(self, name, text):
        path = os.path.join(self.tmp.name, name)
        with open(path, "w", encoding="utf-8") as f:
            f.write(text)
        return path

    def test_version_names_release_licence_and_parts(self):
        p = run("--version")
        self.assertEqual(p.returncode, 0, p.stderr)
        first = p.stdout.splitlines()[0]
        self.assertRegex(first, r"^vrsph \d+\.\d+\.\d+ \(BSD-3-Clause\)$")
        self.assertIn("built without:", p.stdout)
        self.assertLessEqual(self.built, {"PETSC", "MPI", "CGAL", "CLP", "SUITESPARSE", "MUPARSER", "VTK_XML", "JSON", "TOML", "OPENMP"})

    def test_json_output_needs_no_part(self):
        """Writing JSON is the core's own (vrsph/io/json.hpp): tables and metadata in every build."""
        p = run("operator", "--problem", "qw-trunc", "--method", "sph", "--operator", "gradient", "--cloud", "uniform",
                "--n", "8,16", "--format", "json")
        self.assertEqual(p.returncode, 0, p.stderr)
        doc = json.loads(p.stdout)
        self.assertEqual([r["n"] for r in doc["rows"]], [8, 16])
        self.assertEqual(doc["dim"], 2)
        self.assertIsNone(doc["rows"][0]["order_inf"])  # the first row has no order: null, not NaN
        self.assertIsInstance(doc["rows"][0]["error_inf"], float)
        self.assertIn("fitted_order_inf", doc)
        p = run("methods", "--format", "json")
        self.assertEqual(p.returncode, 0, p.stderr)
        rows = json.loads(p.stdout)
        self.assertTrue(all(r["reference"] is None or r["reference"]["year"] > 1900 for r in rows))

    def test_core_solve_works_in_every_build(self):
        p = run("solve", "--n", "16", "--format", "json")
        self.assertEqual(p.returncode, 0, p.stderr)
        row = json.loads(p.stdout)["rows"][0]
        self.assertLess(row["error_inf"], 1e-2)
        # auto chose a solver this build has
        solver = row.get("solver", "")
        if "SUITESPARSE" not in self.built:
            self.assertNotIn("umfpack", solver)
        # the VTU output works without zlib too (uncompressed arrays then)
        vtu = os.path.join(self.tmp.name, "u.vtu")
        p = run("solve", "--n", "12", "--vtu", vtu)
        self.assertEqual(p.returncode, 0, p.stderr)
        with open(vtu, encoding="utf-8") as f:
            head = f.read(400)
        self.assertEqual("vtkZLibDataCompressor" in head, "VTK_XML" in self.built)

    def test_binary_vtu_decodes_to_the_ascii_values(self):
        """Binary VTU arrays (zlib-compressed with VTK_XML, raw without) hold exactly the ascii values."""
        paths = {}
        for fmt in ("binary", "ascii"):
            paths[fmt] = os.path.join(self.tmp.name, f"{fmt}.vtu")
            p = run("cloud", "--family", "perturbed", "--n", "7", "--seed", "3", "--output", paths[fmt], "--vtu-format", fmt)
            self.assertEqual(p.returncode, 0, p.stderr)
        texts = {}
        for fmt, path in paths.items():
            with open(path, encoding="utf-8") as f:
                texts[fmt] = f.read()
        ascii_text, binary_text = texts["ascii"], texts["binary"]
        pattern = r"<Points>\s*<DataArray[^>]*>\s*(.*?)\s*</DataArray>"
        expected = [float(v) for v in re.search(pattern, ascii_text, re.S).group(1).split()]
        encoded = re.search(pattern, binary_text, re.S).group(1)
        if "vtkZLibDataCompressor" in binary_text:
            # two base64 streams: header [nblocks, block, last, sizes...], then the blocks
            nblocks = struct.unpack("<Q", base64.b64decode(encoded[:12])[:8])[0]
            header_len = 4 * ((8 * (3 + nblocks) + 2) // 3)
            header = struct.unpack(f"<{3 + nblocks}Q", base64.b64decode(encoded[:header_len]))
            blob = base64.b64decode(encoded[header_len:])
            raw, at = b"", 0
            for size in header[3:]:
                raw += zlib.decompress(blob[at:at + size])
                at += size
        else:
            data = base64.b64decode(encoded)
            size = struct.unpack("<Q", data[:8])[0]
            raw = data[8:8 + size]
            self.assertEqual(len(raw), size)
        values = struct.unpack(f"<{len(raw) // 8}d", raw)
        self.assertEqual(list(values), expected)

    def case(self, part, args, cwd=None):
        p = run(*args, cwd=cwd)
        if part in self.built:
            self.assertNotIn("vrsph was built without", p.stderr, args)
            return
        self.assertEqual(p.returncode, 2, (args, p.stdout, p.stderr))
        self.assertIn(f"vrsph was built without {part}", p.stderr)
        self.assertIn(f"-DVRSPH_WITH_{part}=ON", p.stderr)
        self.assertEqual(p.stderr.count("\n"), 1, p.stderr)  # one line

    def test_each_missing_part_is_named(self):
        self.case("PETSC", ("solve", "--n", "12", "--solver", "petsc"))
        self.case("SUITESPARSE", ("solve", "--n", "12", "--solver", "umfpack"))
        self.case("CGAL", ("cloud", "--geometry", self.file("cube.off", CUBE_OFF), "--spacing", "0.25"))
        self.case("CGAL", ("cloud", "--family", "centroids", "--n", "8"))
        vtu = self.file("c.vtu", '<?xml version="1.0"?><VTKFile type="UnstructuredGrid"></VTKFile>\n')
        self.case("VTK_XML", ("cloud", "--input", vtu))
        square = self.file("square.geojson", '{"type": "Polygon", "coordinates": [[[0,0],[1,0],[1,1],[0,1],[0,0]]]}')
        self.case("JSON", ("cloud", "--geometry", square, "--spacing", "0.25"))
        self.case("TOML", ("solve", "--config", self.file("p.toml", "n = 12\n")))
        # The regularity report needs CGAL's Voronoi cells before Clp's LP: the first part missing is named.
        self.case("CLP" if "CGAL" in self.built else "CGAL",
                  ("cloud", "--family", "perturbed", "--n", "6", "--regularity", "--dn-method", "lp"))


if __name__ == "__main__":
    unittest.main()
