#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""`cmake --install` into a prefix the user cannot write to stops before copying anything, with a
message naming a prefix that works (issue 36). Run as root: the install runs as `nobody`
(setpriv), for whom /opt is read-only. Skipped (exit 0, saying so) when not root or without setpriv.

usage: test_install_prefix.py BUILD_DIR"""
import os
import shutil
import subprocess
import sys

build = os.path.abspath(sys.argv[1])
if os.geteuid() != 0 or shutil.which("setpriv") is None:
    print("skipped: needs root and setpriv to run the install as another user")
    sys.exit(0)
target = "/opt/vrsph-install-test-unwritable"
p = subprocess.run(["setpriv", "--reuid=65534", "--regid=65534", "--clear-groups", "env", "HOME=/home/someone",
                    "cmake", "--install", build, "--prefix", target], capture_output=True, text=True, timeout=120,
                   cwd="/")
out = p.stdout + p.stderr
assert p.returncode != 0, out
assert f"vrsph: cannot install into {target}: /opt is not writable by this user" in " ".join(out.split()), out
assert "--prefix /home/someone/.local" in " ".join(out.split()), out
assert "Installing" not in out, "files were copied before the check: " + out
assert not os.path.exists(target)
print("refused before copying, naming a prefix that works")
