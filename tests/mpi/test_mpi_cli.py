#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""vrsph under mpirun: the same tables as serial, one document from rank 0, .pvtu pieces,
and bad input that ends every rank with the same non-zero exit (no hang: each run has a
timeout). Usage: test_mpi_cli.py MPIRUN VRSPH"""
import json
import os
import subprocess
import sys
import tempfile
import unittest

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "convergence"))
from test_units_and_limits import in_unit, scaled_cloud  # noqa: E402  (the same scaled clouds as serial)

MPIRUN, VRSPH = sys.argv[1], sys.argv[2]
DIRECT = "-ksp_type preonly -pc_type lu -pc_factor_mat_solver_type mumps"
ENV = dict(os.environ, OMP_NUM_THREADS="1")


def run(ranks, *args, timeout=240, cwd=None):
    cmd = [VRSPH, *args] if ranks == 0 else [MPIRUN, "--allow-run-as-root", "--oversubscribe", "-np", str(ranks), VRSPH, *args]
    return subprocess.run(cmd, capture_output=True, text=True, timeout=timeout, env=ENV, cwd=cwd)


def run_json(ranks, *args):
    p = run(ranks, *args, "--format", "json")
    if p.returncode != 0:
        raise AssertionError(f"{ranks} ranks: vrsph {' '.join(args)} exited {p.returncode}: {p.stderr}")
    return json.loads(p.stdout)  # exactly one document: only rank 0 prints


def close(a, b, rtol, atol):
    """|b - a| <= rtol |a| + atol: errors near round-off (the compact rows are exact on
    quadratics) are compared in absolute terms, larger ones relatively."""
    return abs(b - a) <= rtol * abs(a) + atol


class SameTables(unittest.TestCase):
    def compare(self, args, rtol, ranks=(2, 4), atol=1e-12):
        serial = run_json(0, *args)
        for r in ranks:
            par = run_json(r, *args)
            self.assertEqual(par["ranks"], r)
            self.assertEqual(len(par["rows"]), len(serial["rows"]))
            for a, b in zip(serial["rows"], par["rows"]):
                for key in ("N", "unknowns", "infeasible", "mmatrix"):
                    self.assertEqual(a[key], b[key], key)
                for key in ("error_inf", "error_l2"):
                    self.assertTrue(close(a[key], b[key], rtol, atol), f"{key} with {r} ranks: {b[key]} vs {a[key]}")
                for key in ("nnz_per_row", "neighbours_mean"):
                    self.assertAlmostEqual(b[key] / a[key], 1.0, delta=rtol, msg=f"{key} with {r} ranks: {b[key]} vs {a[key]}")

    def test_example5_direct(self):
        self.compare(["study", "--problem", "qw-ex5", "--method", "vrsph,sph", "--cloud", "perturbed", "--n", "20,40",
                      "--solver", "petsc", "--petsc-options", DIRECT], 1e-10)

    def test_periodic_boxes_direct(self):
        # Images across the periodic faces are halo entries; a fully periodic box's pinned
        # particle and its spread defect live on one rank.
        self.compare(["study", "--periodic", "x,y", "--u", "sin(2*pi*x)*cos(2*pi*y)", "--method", "vrsph,sph",
                      "--cloud", "perturbed", "--n", "16,32", "--solver", "petsc", "--petsc-options", DIRECT], 1e-9,
                     ranks=(2, 3))
        self.compare(["study", "--dim", "3", "--periodic", "x,z", "--u", "sin(2*pi*x)*exp(y)*cos(2*pi*z)",
                      "--method", "vrsph", "--cloud", "perturbed", "--n", "8,12", "--solver", "petsc",
                      "--petsc-options", DIRECT], 1e-9, ranks=(2,))
        self.compare(["study", "--periodic", "y", "--layout", "cells", "--u", "exp(x)*sin(2*pi*y)", "--method", "vrsph",
                      "--cloud", "perturbed", "--n", "12,24", "--solver", "petsc", "--petsc-options", DIRECT], 1e-9,
                     ranks=(3, 4))

    def test_mixed_3d_direct(self):
        self.compare(["study", "--dim", "3", "--u", "sin(x)*exp(y)+z^2", "--a", "1+x*y", "--neumann", "x1,z0",
                      "--method", "vrsph", "--cloud", "perturbed", "--n", "6,10", "--solver", "petsc",
                      "--petsc-options", DIRECT], 1e-10, ranks=(2,))

    def test_robin_and_tensor_mobility_direct(self):
        # FPM's default Robin rows are exact on cubics: one-sided rows with larger weights of both
        # signs, so the ranks' other summation order shows at 1.3e-9 relative (measured; 1e-10
        # with the linear fit's rows).
        self.compare(["study", "--u", "x*y+exp(x)", "--robin", "x1,y0", "--beta", "1+x", "--method", "vrsph,fpm",
                      "--cloud", "perturbed", "--n", "12,24", "--solver", "petsc", "--petsc-options", DIRECT], 1e-8,
                     ranks=(2,))
        self.compare(["study", "--u", "sin(x)*cos(y)", "--mobility", "1+x^2,2+y", "--method", "m-sph,vrsph",
                      "--cloud", "perturbed", "--n", "12,24", "--solver", "petsc", "--petsc-options", DIRECT], 1e-10,
                     ranks=(2,))

    def test_centroid_and_disk_clouds_made_per_rank_with_covering_h(self):
        for cloud in ("centroids", "disk"):
            self.compare(["study", "--problem", "qw-ex5", "--method", "vrsph", "--cloud", cloud, "--n", "16,24",
                          "--h-mode", "covering", "--solver", "petsc", "--petsc-options", DIRECT], 1e-10, ranks=(3,))

    def test_issue_command_with_amg(self):
        # GMRES + BoomerAMG to rtol 1e-10 on both sides: equal to the solver's tolerance.
        self.compare(["study", "--problem", "qw-ex5", "--method", "vrsph", "--cloud", "perturbed", "--n", "40,80",
                      "--solver", "petsc"], 1e-6, ranks=(2,), atol=1e-10)


class HeterogeneousStudy(unittest.TestCase):
    """vrsph study --problem spe-*: every particle method's solve over the ranks; the table
    against TPFA as in serial (MUMPS on both sides), the fields written once by rank 0, and
    the Krylov study refused (it re-solves each assembled system serially)."""

    def test_channel_as_serial_and_fields_written_once(self):
        args = ["study", "--problem", "spe-channel", "--n", "20", "--method", "vrsph,m-sph,tpfa", "--solver", "petsc",
                "--petsc-options", DIRECT]
        serial = run_json(0, *args)
        with tempfile.TemporaryDirectory() as d:
            par = run_json(2, *args, "--vtu", os.path.join(d, "fields.vtu"))
            self.assertEqual(sorted(os.listdir(d)), ["fields.vtu"])
        self.assertEqual(len(par["rows"]), len(serial["rows"]))
        for a, b in zip(serial["rows"], par["rows"]):
            self.assertEqual(a["method"], b["method"])
            for key in ("unknowns", "mmatrix", "monotone"):
                self.assertEqual(a[key], b[key], key)
            for key in ("error_rel_vs_tpfa", "error_rms_rel_vs_tpfa", "outlet_flux", "flux_error_vs_tpfa"):
                self.assertTrue(close(a[key], b[key], 1e-9, 1e-12), f"{a['method']} {key}: {b[key]} vs {a[key]}")

    def test_krylov_study_refused(self):
        out = run(2, "study", "--problem", "spe-channel", "--n", "12", "--krylov", "jacobi")
        self.assertEqual(out.returncode, 2)
        self.assertIn("runs on one rank", out.stderr)


class Diffusion(unittest.TestCase):
    """vrsph diffuse on the ranks' slices: the serial error table (explicit steps with the Neumann
    block, the [SPE] plate; Crank-Nicolson with a direct parallel solve)."""

    def compare(self, args, rtol, ranks=(2, 3)):
        serial = run_json(0, "diffuse", *args)
        for r in ranks:
            par = run_json(r, "diffuse", *args)
            self.assertEqual(len(par["rows"]), len(serial["rows"]))
            for a, b in zip(serial["rows"], par["rows"]):
                self.assertEqual(a["steps"], b["steps"])
                self.assertEqual(a["particles"], b["particles"])
                self.assertTrue(close(a["error_inf"], b["error_inf"], rtol, 1e-14),
                                f"error_inf with {r} ranks: {b['error_inf']} vs {a['error_inf']}")

    def test_explicit_with_neumann_rows(self):
        self.compare(["--u", "exp(-t)*sin(x)*cos(y)", "--dim", "2", "--n", "20", "--cloud", "perturbed",
                      "--t-end", "0.01", "--dt", "0.0002", "--neumann", "x0,x1", "--method", "fpm", "--h-factor", "1.5"],
                     1e-10)

    def test_plate_explicit_and_crank_nicolson(self):
        self.compare(["--t-end", "1"], 1e-12)
        self.compare(["--t-end", "1", "--scheme", "cn", "--nu", "1", "--solver", "petsc", "--petsc-options", DIRECT],
                     1e-9)

    def test_vtu_series_refused(self):
        out = run(2, "diffuse", "--t-end", "1", "--vtu-series", "s")
        self.assertEqual(out.returncode, 2)
        self.assertIn("--vtu-series writes the whole field on one rank", out.stderr)


class Output(unittest.TestCase):
    def test_solve_writes_pieces_and_pvtu(self):
        with tempfile.TemporaryDirectory() as d:
            p = run(2, "solve", "--method", "vrsph", "--cloud", "perturbed", "--n", "16", "--vtu", "out.vtu",
                    "--format", "json", cwd=d)
            self.assertEqual(p.returncode, 0, p.stderr)
            self.assertEqual(sorted(os.listdir(d)), ["out.pvtu", "out_0.vtu", "out_1.vtu"])
            with open(os.path.join(d, "out.pvtu")) as f:
                text = f.read()
            self.assertIn('Source="out_1.vtu"', text)
            self.assertIn('Name="U"', text)
            self.assertEqual(json.loads(p.stdout)["rows"][0]["ranks"], 2)


    def test_users_cloud_file(self):
        # Every rank reads the file and keeps its slice; same errors as serial, pieces written.
        with tempfile.TemporaryDirectory() as d:
            self.assertEqual(run(0, "cloud", "--family", "perturbed", "--n", "30", "--output", "c.csv", cwd=d).returncode, 0)
            args = ["solve", "--cloud-file", "c.csv", "--u", "sin(x)*exp(y)",
                    "--method", "vrsph", "--solver", "petsc", "--petsc-options", DIRECT, "--vtu", "s.vtu", "--format", "json"]
            serial = run(0, *args, cwd=d)
            par = run(2, *args, cwd=d)
            self.assertEqual(serial.returncode, 0, serial.stderr)
            self.assertEqual(par.returncode, 0, par.stderr)
            a, b = json.loads(serial.stdout)["rows"][0], json.loads(par.stdout)["rows"][0]
            for key in ("particles", "unknowns", "infeasible", "mmatrix"):
                self.assertEqual(a[key], b[key], key)
            for key in ("error_inf", "error_l2", "error_inf_interior", "error_inf_boundary"):
                self.assertTrue(close(a[key], b[key], 1e-9, 1e-12), f"{key}: {b[key]} vs {a[key]}")
            self.assertEqual(b["vtu"], "s.pvtu")
            self.assertTrue(os.path.exists(os.path.join(d, "s_1.vtu")))
            # Byte ranges of the CSV on 3 ranks, and a VTU file read on rank 0 and scattered.
            self.assertEqual(run(0, "cloud", "--input", "c.csv", "--output", "c.vtu", cwd=d).returncode, 0)
            for ranks, name in ((3, "c.csv"), (2, "c.vtu")):
                p = run(ranks, *[name if x == "c.csv" else x for x in args], cwd=d)
                self.assertEqual(p.returncode, 0, p.stderr)
                c = json.loads(p.stdout)["rows"][0]
                self.assertEqual(c["particles"], a["particles"])
                for key in ("error_inf", "error_l2", "h", "spacing"):
                    self.assertTrue(close(a[key], c[key], 1e-9, 1e-12), f"{key} from {name} on {ranks} ranks")


    def test_geometry_filled_in_parts(self):
        # A lattice fill makes only each rank's layers (rank 0 also the surface); blue noise
        # is made whole on every rank. Both give the serial solve.
        cube = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "errors", "fixtures", "cube.off")
        for fill in ("perturbed", "blue-noise"):
            args = ["solve", "--geometry", cube, "--spacing", "0.125", "--fill", fill, "--u", "x*y+z^2", "--method", "vrsph",
                    "--solver", "petsc", "--petsc-options", DIRECT, "--format", "json"]
            serial, par = run(0, *args), run(3, *args)
            self.assertEqual(serial.returncode, 0, serial.stderr)
            self.assertEqual(par.returncode, 0, par.stderr)
            a, b = json.loads(serial.stdout)["rows"][0], json.loads(par.stdout)["rows"][0]
            self.assertEqual(a["particles"], b["particles"], fill)
            for key in ("error_inf", "error_l2", "h"):
                self.assertTrue(close(a[key], b[key], 1e-9, 1e-12), f"{key} {fill}: {b[key]} vs {a[key]}")


class LengthUnits(unittest.TestCase):
    """Issue 31 on several ranks: the distributed pipeline scales its tolerances, moment systems
    and derived data by the whole cloud's unit, so the same cloud in units 1e-8, 1 and 1e8 gives
    the serial errors on 2 ranks, with the published rows and with the default's compact rows."""

    def test_scaled_clouds_on_two_ranks_equal_serial(self):
        cases = ((("--method-opt", "vrsph:profile=qw"), "sin(x)*cos(2*y)", "-5*sin(x)*cos(2*y)"),
                 ((), "sin(x)*cos(2*y)", "-5*sin(x)*cos(2*y)"), ((), "x^2*y+x*y^2", "2*y+2*x"))
        with tempfile.TemporaryDirectory() as d:
            self.assertEqual(run(0, "cloud", "--family", "perturbed", "--n", "16", "--seed", "3", "--output", "c.csv",
                                 cwd=d).returncode, 0)
            for opts, u, lap in cases:
                errors = []
                for s in (1e-8, 1.0, 1e8):
                    name = f"c_{s!r}.csv"
                    scaled_cloud(os.path.join(d, name), os.path.join(d, "c.csv"), s)
                    args = ["solve", "--cloud-file", name, "--u", in_unit(u, s), "--f", f"({in_unit(lap, s)})/{s!r}^2",
                            "--method", "vrsph", *opts, "--solver", "petsc", "--petsc-options", DIRECT, "--format", "json"]
                    for ranks in (0, 2):
                        p = run(ranks, *args, cwd=d)
                        self.assertEqual(p.returncode, 0, f"{ranks} ranks, unit {s}: {p.stderr}")
                        errors.append(json.loads(p.stdout)["rows"][0]["error_inf"])
                with self.subTest(opts=opts, u=u):
                    self.assertLess(max(errors) - min(errors), 1e-10, f"errors (serial, 2 ranks) per unit: {errors}")


class DataOnSomeRanks(unittest.TestCase):
    """Issue 30: a file whose Neumann particles are listed last gives ranks without any; their
    part has no flux data q, and the distributed solve must still equal the serial one."""

    def test_neumann_particles_listed_last(self):
        with tempfile.TemporaryDirectory() as d:
            self.assertEqual(run(0, "cloud", "--family", "perturbed", "--n", "24", "--output", "c.csv", cwd=d).returncode, 0)
            with open(os.path.join(d, "c.csv")) as f:
                header, *rows = f.read().splitlines()
            # The faces x = 1 and y = 1 become Neumann (outward normals), and those rows go last.
            cols = header.split(",")
            out, wall = [], []
            for line in rows:
                v = dict(zip(cols, line.split(",")))
                x, y = float(v["x"]), float(v["y"])
                if v["tag"] == "dirichlet" and (x > 1 - 1e-12 or y > 1 - 1e-12) and min(x, y) > 1e-12:
                    n = (1.0, 0.0) if x > 1 - 1e-12 and y < 1 - 1e-12 else (0.0, 1.0) if x < 1 - 1e-12 else (0.7071067811865476,) * 2
                    wall.append(f"{x!r},{y!r},neumann,{n[0]!r},{n[1]!r}")
                else:
                    out.append(f"{x!r},{y!r},{v['tag']},0,0")
            with open(os.path.join(d, "last.csv"), "w") as f:
                f.write("x,y,tag,nx,ny\n" + "\n".join(out + wall) + "\n")
            # Also every boundary particle last: the first ranks then hold interior particles only.
            inner = [r for r in out if ",interior," in r]
            with open(os.path.join(d, "sorted.csv"), "w") as f:
                f.write("x,y,tag,nx,ny\n" + "\n".join(inner + [r for r in out if r not in inner] + wall) + "\n")
            for name, solver in (("last.csv", ("--solver", "petsc", "--petsc-options", DIRECT)), ("last.csv", ()),
                                 ("sorted.csv", ("--solver", "petsc", "--petsc-options", DIRECT))):
                args = ["solve", "--cloud-file", name, "--u", "exp(x)*sin(2*y)+x^2", *solver, "--format", "json"]
                serial = run(0, *args, cwd=d)
                self.assertEqual(serial.returncode, 0, serial.stderr)
                a = json.loads(serial.stdout)["rows"][0]
                for ranks in (2, 3):
                    p = run(ranks, *args, cwd=d, timeout=120)
                    self.assertEqual(p.returncode, 0, f"{ranks} ranks: {p.stderr}")
                    b = json.loads(p.stdout)["rows"][0]
                    self.assertEqual(a["unknowns"], b["unknowns"])
                    for key in ("error_inf", "error_l2"):  # iterative (AMG, rtol 1e-10) or direct: to 1e-9 in u
                        self.assertTrue(close(a[key], b[key], 0, 1e-9 if not solver else 1e-12),
                                        f"{key} of {name} on {ranks} ranks {solver}: {b[key]} vs {a[key]}")


class FaultOnOneRank(unittest.TestCase):
    """Issue 30: a failure in any stage on any one rank ends every rank promptly with the
    same exit code (no hang): inside the library's collectives it is agreed and reported once,
    elsewhere the failing rank reports it and MPI_Abort ends the others."""

    def test_every_stage(self):
        with tempfile.TemporaryDirectory() as d:
            self.assertEqual(run(0, "cloud", "--family", "perturbed", "--n", "16", "--output", "c.csv", cwd=d).returncode, 0)
            for stage in ("read", "problem", "distribute", "neighbours", "stencil", "assemble", "solve", "output"):
                for rank in (0, 1):
                    env = dict(ENV, VRSPH_INJECT_FAULT=f"{stage}@{rank}")
                    cmd = [MPIRUN, "--allow-run-as-root", "-np", "2", "-x", "VRSPH_INJECT_FAULT", VRSPH, "solve",
                           "--cloud-file", "c.csv", "--u", "x*y", "--solver", "petsc", "--vtu", "u.vtu"]
                    p = subprocess.run(cmd, capture_output=True, text=True, timeout=60, env=env, cwd=d)
                    self.assertEqual(p.returncode, 5, f"{stage}@{rank}: {p.stderr}")
                    self.assertIn(f"injected fault at stage '{stage}' on rank {rank}", p.stderr, stage)
                    self.assertEqual(p.stderr.count("vrsph: "), 1, f"{stage}@{rank}: one message: {p.stderr}")


class BadInput(unittest.TestCase):
    def expect(self, ranks, code, fragment, *args):
        p = run(ranks, *args, timeout=120)
        self.assertEqual(p.returncode, code, p.stderr)
        self.assertIn(fragment, p.stderr)
        self.assertEqual(p.stderr.count("vrsph: "), 1, "one message, from rank 0: " + p.stderr)

    def expect_on_file(self, ranks, code, fragment, text, *args):
        # The same, for a cloud file `c.csv` holding `text`.
        with tempfile.TemporaryDirectory() as d:
            with open(os.path.join(d, "c.csv"), "w") as f:
                f.write(text)
            self.expect(ranks, code, fragment, "solve", "--cloud-file", os.path.join(d, "c.csv"), *args)

    def test_bad_row_of_a_cloud_file_read_in_parallel(self):
        rows = "".join(f"{i / 100},{(i * 7 % 100) / 100},interior\n" for i in range(300))
        self.expect_on_file(3, 3, "c.csv:302: column y is not finite", "x,y,tag\n" + rows + "0.5,nan,interior\n",
                            "--u", "x", "--solver", "petsc")

    def test_cloud_file_smaller_than_the_ranks(self):
        # A rank whose byte range holds no row is allowed; the whole cloud's problem is named.
        self.expect_on_file(3, 4, "the cloud has only 1 particle", "x,y,tag\n0.5,0.5,interior\n",
                            "--u", "x", "--solver", "petsc")

    def test_serial_only_command(self):
        self.expect(2, 2, "runs on one rank", "cloud", "--family", "perturbed", "--n", "8")

    def test_more_ranks_than_particles(self):
        self.expect(4, 2, "more ranks (4) than particles (3)", "study", "--dim", "1", "--n", "2", "--h-factor", "1.5", "--solver", "petsc")

    def test_serial_solver_refused(self):
        self.expect(2, 2, "runs on one rank only", "study", "--n", "10", "--solver", "umfpack")

    def test_failure_inside_the_pipeline(self):
        # A support below the spacing: no neighbours; found on some rank, reported once by all.
        self.expect(2, 4, "neighbours", "study", "--n", "10", "--h-factor", "0.5", "--solver", "petsc")


class RanksOption(unittest.TestCase):
    """Issue 37: `vrsph --ranks P` starts mpirun itself (one thread per rank) and gives the
    table of `mpirun -np P vrsph`; it refuses what it cannot do."""

    def test_same_table_as_mpirun_and_as_serial(self):
        args = ["study", "--cloud", "perturbed", "--n", "20,40", "--solver", "petsc", "--petsc-options", DIRECT]
        serial = run_json(0, *args)
        relaunched = run_json(0, "--ranks", "2", *args)
        self.assertEqual(relaunched["ranks"], 2)
        self.assertEqual(serial["ranks"], 1)
        for a, b in zip(serial["rows"], relaunched["rows"]):
            self.assertEqual(a["N"], b["N"])
            self.assertTrue(close(a["error_inf"], b["error_inf"], 1e-10, 1e-12), (a["error_inf"], b["error_inf"]))
        # The option may also follow the command; --ranks 1 is this process.
        self.assertEqual(run_json(0, "bench", "solve", "--n", "16", "--ranks", "2")["ranks"], 2)
        self.assertEqual(run_json(0, "--ranks", "1", "study", "--n", "8")["ranks"], 1)

    def test_refusals(self):
        for args, message in ((["--ranks", "0", "study", "--n", "8"], ">= 1"),
                              (["--ranks", "4096", "study", "--n", "8"], "cores"),
                              (["--ranks", "2", "cloud", "--n", "8"], "applies to study, solve, diffuse and bench solve")):
            p = run(0, *args)
            self.assertEqual(p.returncode, 2, (args, p.stderr))
            self.assertIn(message, p.stderr)
        p = run(2, "--ranks", "3", "study", "--n", "8")
        self.assertEqual(p.returncode, 2, p.stderr)
        self.assertIn("give the ranks one way, not both", p.stderr)
        # A peer on several ranks would need an mpirun inside vrsph's own: refused by name (each
        # rank sees only its share of the cores, which the check of the cores used to report).
        p = run(2, "bench", "solve", "--n", "8", "--anchor", "fenicsx", "--anchor-ranks", "2")
        self.assertEqual(p.returncode, 2, p.stderr)
        self.assertIn("the peer cannot start its own mpirun inside vrsph's", p.stderr)


if __name__ == "__main__":
    unittest.main(argv=sys.argv[:1], verbosity=2)
