# SPDX-License-Identifier: BSD-3-Clause
"""Issue 31, class 9: the Python API checks its arguments itself. A wrong value or type is a
vrsph.Error subclass that names the parameter (ConfigError: a ValueError; ArgumentTypeError: a
TypeError), never a silent default (h=nan used the default h), a truncation (n=[8.7] ran n=8)
or pybind11's "Unable to cast Python instance to C++ type"."""
import math

import numpy as np
import pytest

import vrsph


@pytest.fixture(scope="module")
def cloud():
    return vrsph.cloud.perturbed(dim=2, n=10, seed=1)


@pytest.mark.parametrize("h", [float("nan"), -1.0, 0.0, float("inf")])
def test_stencil_refuses_a_support_radius_that_is_not_a_positive_number(cloud, h):
    with pytest.raises(vrsph.ConfigError, match="the parameter h"):
        vrsph.stencil(cloud, h=h)


def test_solve_refuses_bad_numbers_and_names_them(cloud):
    with pytest.raises(vrsph.ConfigError, match="the parameter h "):
        vrsph.solve(cloud, u="x", h=float("nan"))
    with pytest.raises(vrsph.ConfigError, match="the parameter h_factor"):
        vrsph.solve(cloud, u="x", h_factor=-3)
    with pytest.raises(vrsph.ArgumentTypeError, match="the parameter h_factor must be a number"):
        vrsph.solve(cloud, u="x", h_factor="3")
    with pytest.raises(TypeError):  # also a built-in TypeError
        vrsph.solve(cloud, u="x", method=3)


def test_study_refuses_non_integral_sizes_and_wrong_types():
    with pytest.raises(vrsph.ConfigError, match=r"the parameter n\[0\] must be an integer, got 8.7"):
        vrsph.study(n=[8.7])
    with pytest.raises(vrsph.ArgumentTypeError, match=r"the parameter n\[1\]"):
        vrsph.study(n=[8, "16"])
    with pytest.raises(vrsph.ArgumentTypeError, match="the parameter methods"):
        vrsph.study(methods=[1], n=[8])
    with pytest.raises(vrsph.ConfigError, match="the parameter seeds"):
        vrsph.study(n=[8], seeds=[-1])
    for bad in (True, [], "8"):
        with pytest.raises(vrsph.Error):
            vrsph.study(n=bad)


def test_integral_floats_and_numbers_as_expressions_are_accepted(cloud):
    rows = vrsph.study(n=[8.0, 16], a=2.0, u="sin(pi*x)*sin(pi*y)")
    assert [r["n"] for r in rows] == [8, 16]
    direct = vrsph.study(n=[8, 16], a="2", u="sin(pi*x)*sin(pi*y)")
    assert rows[1]["error_inf"] == pytest.approx(direct[1]["error_inf"], rel=1e-12)
    s = vrsph.solve(cloud, u="x*y", a=2.0)
    assert s.error_inf < 1e-6
    assert math.isfinite(vrsph.solve(cloud, u="x", h=np.float64(0.3)).error_inf)


def test_write_vtu_refuses_a_second_tag_array(cloud, tmp_path):
    path = str(tmp_path / "c.vtu")
    with pytest.raises(vrsph.InputError, match="reserved"):
        vrsph.write_vtu(path, cloud, {"tag": np.zeros(len(cloud))})
    with pytest.raises(vrsph.InputError, match="given twice"):
        vrsph.write_vtu(path, cloud, {"u": np.zeros(len(cloud)), "U": np.ones(len(cloud))})
    vrsph.write_vtu(path, cloud, {"u": np.arange(len(cloud), dtype=float)})
    back = vrsph.read_cloud(path)
    assert np.array_equal(back.fields["u"], np.arange(len(cloud), dtype=float))


def test_normals_are_scaled_to_unit_length_and_short_ones_refused():
    pts = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [1.0, 1.0], [0.5, 0.5]])
    tags = np.array([1, 2, 1, 1, 0])
    normals = np.array([[0.0, 0.0], [2.0, 0.0], [0.0, 0.0], [0.0, 0.0], [0.0, 0.0]])
    c = vrsph.cloud.from_arrays(pts, tags, normals)
    assert np.allclose(c.normals[1], [1.0, 0.0])
    normals[1] = [1e-9, 0.0]
    with pytest.raises(vrsph.InputError, match="too short to give a direction"):
        vrsph.cloud.from_arrays(pts, tags, normals)


def test_ctrl_c_stops_a_long_call_within_a_second():
    """Issue 31, class 8: SIGINT during a library call raises KeyboardInterrupt promptly (the
    library polls Python's signal handlers between stages and inside its long loops)."""
    import os
    import signal
    import threading
    import time

    cloud = vrsph.cloud.perturbed(dim=2, n=500, seed=2)  # a solve of several seconds
    for call in (lambda: vrsph.solve(cloud, u="sin(pi*x)*sin(pi*y)"),
                 lambda: vrsph.stencil(cloud, options={"profile": "qw"})):
        state = {}

        def interrupt():
            state["running"] = "done" not in state
            state["at"] = time.monotonic()
            os.kill(os.getpid(), signal.SIGINT)

        timer = threading.Timer(0.3, interrupt)
        timer.start()
        with pytest.raises(KeyboardInterrupt):
            call()
            state["done"] = True
            time.sleep(30)  # (only when the call was faster than the timer; asserted below)
        timer.join()
        assert state["running"], "the call ended before the signal: make it longer"
        assert time.monotonic() - state["at"] < 1.0
