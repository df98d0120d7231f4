#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""Issue 31 (hostile input, second round): the classes that need more than one command line
to show (environment, signals, write failures, files read back, geometry orientation).
The single-command classes are rows of docs/errors.md (the errors_catalogue test).

Usage: test_hostile_round2.py PATH_TO_VRSPH
"""
import csv
import os
import resource
import signal
import subprocess
import sys
import tempfile
import textwrap
import time
import unittest

VRSPH = None


def run(*args, cwd=None, env=None, preexec_fn=None):
    return subprocess.run([VRSPH, *args], capture_output=True, text=True, timeout=300, cwd=cwd, env=env,
                          preexec_fn=preexec_fn, stdin=subprocess.DEVNULL)


class OpenMpEnvironment(unittest.TestCase):
    """An absurd OMP_NUM_THREADS (libgomp tried to start them all) is capped like --threads;
    an unusable OMP_STACKSIZE is a configuration error (exit 2), not libgomp's exit 1."""

    def test_thread_count_beyond_the_cores_is_capped_with_a_warning(self):
        p = run("study", "--n", "8", "--format", "json", env=dict(os.environ, OMP_NUM_THREADS="100000000"))
        self.assertEqual(p.returncode, 0, p.stderr)
        if os.environ.get("VRSPH_TEST_OPENMP", "1") == "1":  # (the sanitizer build has no OpenMP)
            self.assertIn("asks for more threads than the", p.stderr)

    def test_unusable_stack_sizes_are_configuration_errors(self):
        for value in ("1000000G", "abc", "-5M", "0"):
            p = run("study", "--n", "8", env=dict(os.environ, OMP_STACKSIZE=value))
            self.assertEqual(p.returncode, 2, f"OMP_STACKSIZE={value}: {p.stderr}")
            self.assertIn("OMP_STACKSIZE", p.stderr)
        p = run("study", "--n", "8", env=dict(os.environ, OMP_STACKSIZE="16M"))
        self.assertEqual(p.returncode, 0, p.stderr)


def limit_file_size(limit):
    def apply():
        signal.signal(signal.SIGXFSZ, signal.SIG_IGN)  # a write past the limit fails (EFBIG)
        resource.setrlimit(resource.RLIMIT_FSIZE, (limit, limit))
    return apply


class AtomicWrites(unittest.TestCase):
    """A write that fails half-way leaves the previous file as it was, and no temporary."""

    def test_a_failed_write_keeps_the_previous_file(self):
        with tempfile.TemporaryDirectory() as work:
            written = []
            for command, option, name in (("solve", "--vtu", "u.vtu"), ("study", "--output", "table.json")):
                written.append(name)
                target = os.path.join(work, name)
                with open(target, "w") as f:
                    f.write("previous content\n")
                p = run(command, "--n", "40", option, target, "--format", "json", preexec_fn=limit_file_size(600))
                self.assertEqual(p.returncode, 3, f"{option}: {p.stderr}")
                self.assertIn("the previous file, if any, is unchanged", p.stderr)
                with open(target) as f:
                    self.assertEqual(f.read(), "previous content\n")
                self.assertEqual(sorted(os.listdir(work)), sorted(written))  # no temporary left

    def test_an_interrupted_plot_leaves_no_temporary_and_the_old_png(self):
        """SIGTERM while the plot script writes: the handler removes the temporary and ends the
        run with the signal; Ctrl-C in a terminal (SIGINT to the whole process group) ends the
        script, and the failed plot is reported with the old PNG intact."""
        for sig, group in ((signal.SIGTERM, False), (signal.SIGINT, True)):
            with tempfile.TemporaryDirectory() as work:
                slow = os.path.join(work, "slow_plot.py")
                with open(slow, "w") as f:  # writes part of its output, then hangs until killed
                    f.write(textwrap.dedent("""\
                        import sys, time
                        with open(sys.argv[2], "wb") as out:
                            out.write(b"half a png")
                            out.flush()
                            time.sleep(60)
                        """))
                png = os.path.join(work, "conv.png")
                with open(png, "wb") as f:
                    f.write(b"the old plot")
                env = dict(os.environ, VRSPH_PLOT_SCRIPT=slow)
                p = subprocess.Popen([VRSPH, "study", "--n", "8,16", "--plot", png], env=env, stdout=subprocess.DEVNULL,
                                     stderr=subprocess.PIPE, start_new_session=True)
                deadline = time.time() + 60
                while time.time() < deadline and len(os.listdir(work)) < 3:
                    time.sleep(0.05)
                self.assertEqual(len(os.listdir(work)), 3, "the plot script never started writing")
                time.sleep(0.3)
                if group:
                    os.killpg(p.pid, sig)
                else:
                    p.send_signal(sig)
                p.wait(timeout=30)  # (not communicate: the orphaned script keeps stderr open)
                try:
                    os.killpg(p.pid, signal.SIGKILL)  # the sleeping script, if still there
                except ProcessLookupError:
                    pass
                err = p.stderr.read()
                p.stderr.close()
                if group:
                    self.assertEqual(p.returncode, 3, err)
                    self.assertIn("plotting to", err.decode())
                else:
                    self.assertEqual(p.returncode, -sig)
                self.assertEqual(sorted(os.listdir(work)), ["conv.png", "slow_plot.py"])
                with open(png, "rb") as f:
                    self.assertEqual(f.read(), b"the old plot")

    def test_time_series_collections_list_only_this_runs_files(self):
        with tempfile.TemporaryDirectory() as work:
            prefix = os.path.join(work, "series")
            common = ("diffuse", "--nu", "0.2", "--vtu-series", prefix)
            self.assertEqual(run(*common, "--t-end", "0.4", "--report-times", "0.1,0.2,0.3,0.4").returncode, 0)
            p = run(*common, "--t-end", "0.2", "--report-times", "0.1,0.2")
            self.assertEqual(p.returncode, 0, p.stderr)
            with open(prefix + ".pvd") as f:
                listed = f.read().count("<DataSet ")
            self.assertEqual(listed, 3)  # t = 0, 0.1, 0.2 of the second run
            self.assertFalse(any(".tmp" in n for n in os.listdir(work)))


class Conversions(unittest.TestCase):
    def test_converting_a_cloud_keeps_its_data_columns(self):
        with tempfile.TemporaryDirectory() as work:
            src = os.path.join(work, "in.csv")
            with open(src, "w") as f:
                f.write("x,y,tag,k\n")
                for j in range(6):
                    for i in range(6):
                        edge = i in (0, 5) or j in (0, 5)
                        f.write(f"{i / 5},{j / 5},{'dirichlet' if edge else 'interior'},{1 + i * j}\n")
            vtu, back = os.path.join(work, "c.vtu"), os.path.join(work, "back.csv")
            self.assertEqual(run("cloud", "--input", src, "--output", vtu).returncode, 0)
            p = run("cloud", "--input", vtu, "--output", back)
            self.assertEqual(p.returncode, 0, p.stderr)
            with open(back) as f:
                rows = list(csv.DictReader(f))
            self.assertEqual([float(r["k"]) for r in rows], [1.0 + i * j for j in range(6) for i in range(6)])


class ProblemFiles(unittest.TestCase):
    def test_every_path_in_a_problem_file_is_relative_to_the_file(self):
        with tempfile.TemporaryDirectory() as here, tempfile.TemporaryDirectory() as there:
            toml = os.path.join(there, "problem.toml")
            with open(toml, "w") as f:
                f.write('n = "8,16"\noutput = "table.csv"\nformat = "csv"\nplot = "conv.png"\n')
            p = run("study", "--config", toml, cwd=here)
            self.assertEqual(p.returncode, 0, p.stderr)
            self.assertEqual(os.listdir(here), [])
            self.assertEqual(sorted(os.listdir(there)), ["conv.png", "problem.toml", "table.csv"])
            with open(toml, "w") as f:
                f.write('n = 12\nvtu = "u.vtu"\n')
            p = run("solve", "--config", toml, cwd=here)
            self.assertEqual(p.returncode, 0, p.stderr)
            self.assertIn("u.vtu", os.listdir(there))
            self.assertEqual(os.listdir(here), [])


def cube(lo, hi, inward=False):
    """The 12 triangles of an axis-aligned cube, wound outward (or inward)."""
    (x0, y0, z0), (x1, y1, z1) = lo, hi
    v = [(x0, y0, z0), (x1, y0, z0), (x1, y1, z0), (x0, y1, z0), (x0, y0, z1), (x1, y0, z1), (x1, y1, z1), (x0, y1, z1)]
    quads = [(0, 3, 2, 1), (4, 5, 6, 7), (0, 1, 5, 4), (2, 3, 7, 6), (1, 2, 6, 5), (0, 4, 7, 3)]
    tris = []
    for a, b, c, d in quads:
        tris += [(v[a], v[b], v[c]), (v[a], v[c], v[d])]
    return [t[::-1] for t in tris] if inward else tris


def write_stl(path, solids):
    with open(path, "w") as f:
        for name, tris in solids:
            f.write(f"solid {name}\n")
            for t in tris:
                f.write("facet normal 0 0 0\nouter loop\n")
                for p in t:
                    f.write(f"vertex {p[0]} {p[1]} {p[2]}\n")
                f.write("endloop\nendfacet\n")
            f.write(f"endsolid {name}\n")


def boundary_normals(path):
    with open(path) as f:
        rows = [r for r in csv.DictReader(f) if r["tag"] != "interior"]
    return [((float(r["x"]), float(r["y"]), float(r["z"])), (float(r["nx"]), float(r["ny"]), float(r["nz"])))
            for r in rows]


class SurfaceOrientation(unittest.TestCase):
    """Each shell is oriented by its nesting, whatever the file's winding."""

    def fill(self, work, solids):
        stl, out = os.path.join(work, "g.stl"), os.path.join(work, "c.csv")
        write_stl(stl, solids)
        p = run("cloud", "--geometry", stl, "--spacing", "0.25", "--output", out)
        self.assertEqual(p.returncode, 0, p.stderr)
        return boundary_normals(out)

    def test_a_solid_stored_inverted_among_others_gets_outward_normals(self):
        with tempfile.TemporaryDirectory() as work:
            normals = self.fill(work, [("a", cube((0, 0, 0), (1, 1, 1))), ("b", cube((2, 0, 0), (3, 1, 1), inward=True))])
            for x, n in normals:
                centre = (0.5 if x[0] < 1.5 else 2.5, 0.5, 0.5)
                self.assertGreater(sum((x[k] - centre[k]) * n[k] for k in range(3)), 0, f"inward normal at {x}")

    def test_a_cavity_stored_outward_gets_normals_into_the_cavity(self):
        with tempfile.TemporaryDirectory() as work:
            normals = self.fill(work, [("outer", cube((0, 0, 0), (3, 3, 3))), ("cavity", cube((1, 1, 1), (2, 2, 2)))])
            cavity = [(x, n) for x, n in normals if all(0.9 < x[k] < 2.1 for k in range(3))]
            self.assertGreater(len(cavity), 10)
            for x, n in cavity:  # out of the material: towards the cavity's centre
                self.assertLess(sum((x[k] - 1.5) * n[k] for k in range(3)), 0, f"normal into the material at {x}")

    def test_a_zero_area_face_on_a_closed_surface_is_dropped(self):
        with tempfile.TemporaryDirectory() as work:
            sliver = [((0, 0, 0), (0.5, 0, 0), (1, 0, 0))]  # collinear: on an edge of the cube
            normals = self.fill(work, [("a", cube((0, 0, 0), (1, 1, 1)) + sliver)])
            self.assertGreater(len(normals), 20)


class SurfaceUnits(unittest.TestCase):
    """A solid in any length unit gives the same cloud (the inside test ran for ever at 1e20)."""

    def test_the_same_solid_at_1e_minus_8_and_1e20(self):
        with tempfile.TemporaryDirectory() as work:
            counts = []
            for s in (1e-8, 1.0, 1e20):
                stl, out = os.path.join(work, f"g{s!r}.stl"), os.path.join(work, f"c{s!r}.csv")
                tris = [tuple(tuple(c * s for c in p) for p in t) for t in cube((0, 0, 0), (1, 1, 1))]
                write_stl(stl, [("a", tris)])
                p = run("cloud", "--geometry", stl, "--spacing", repr(0.25 * s), "--output", out)
                self.assertEqual(p.returncode, 0, p.stderr)
                with open(out) as f:
                    rows = list(csv.DictReader(f))
                counts.append((len(rows), sum(r["tag"] == "interior" for r in rows)))
                xs = sorted(float(r["x"]) / s for r in rows)
                self.assertAlmostEqual(xs[0], 0.0, places=9)
                self.assertAlmostEqual(xs[-1], 1.0, places=9)
            self.assertEqual(len(set(counts)), 1, counts)


class LongExpressions(unittest.TestCase):
    def test_an_over_long_expression_is_not_echoed_whole(self):
        expr = "x+" * 10000 + "(("
        p = run("solve", "--n", "8", "--u", expr)
        self.assertEqual(p.returncode, 3, p.stderr[:300])
        self.assertLess(len(p.stderr), 2000)


if __name__ == "__main__":
    VRSPH = os.path.abspath(sys.argv.pop(1))
    unittest.main(verbosity=2)
