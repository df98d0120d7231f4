# SPDX-License-Identifier: BSD-3-Clause
"""The tutorial scripts of examples/python run and say what they promise."""
import os
import subprocess
import sys

import pytest

HERE = os.path.dirname(os.path.abspath(__file__))
EXAMPLES = os.path.join(HERE, "..", "..", "examples", "python")


@pytest.mark.parametrize("script,expect", [
    ("laplacian_random_cloud.py", "VRSPH"),
    ("poisson_user_cloud.py", "max error"),
    ("qw_table2.py", "order"),
])
def test_example(script, expect, tmp_path):
    p = subprocess.run([sys.executable, os.path.join(EXAMPLES, script)], cwd=tmp_path, capture_output=True,
                       text=True, timeout=600)
    assert p.returncode == 0, p.stderr
    assert expect in p.stdout
