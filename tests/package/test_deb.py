#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""The Debian package (issue 36): `cpack -G DEB` in the build directory makes
vrsph_<version>_amd64.deb with the library, headers, CMake package, CLI, man page and Python
module and declared dependencies; unpacked with `dpkg-deb -x` into a prefix, its `vrsph` runs,
its Python module imports, and a consumer project builds against it with find_package(vrsph).

usage: test_deb.py BUILD_DIR CONSUMER_SOURCE WORK_DIR"""
import glob
import os
import sys

from package_util import build_version, fresh, run

BUILD, CONSUMER, WORK = (os.path.abspath(a) for a in sys.argv[1:4])


fresh(WORK)
version = build_version(BUILD)
run(["cpack", "-G", "DEB", "-B", WORK], cwd=BUILD)
debs = glob.glob(os.path.join(WORK, "vrsph_*.deb"))
assert [os.path.basename(d) for d in debs] == [f"vrsph_{version}_amd64.deb"], debs
deb = debs[0]
info = run(["dpkg-deb", "--info", deb])
depends = next(l for l in info.splitlines() if l.strip().startswith("Depends:"))
for needed in ("libeigen3-dev", "python3-numpy", "libc6", "libstdc++6"):
    assert needed in depends, (needed, depends)
files = run(["dpkg-deb", "--contents", deb])
for path in ("./usr/bin/vrsph", "./usr/include/vrsph/vrsph.hpp", "./usr/include/vrsph/config.hpp",
             "./usr/lib/cmake/vrsph/vrsphConfig.cmake", "./usr/share/man/man1/vrsph.1",
             "./usr/lib/python3/dist-packages/vrsph/__init__.py", "./usr/share/doc/vrsph/LICENSE"):
    assert path in files or path.replace("/lib/", "/lib/x86_64-linux-gnu/", 1) in files, path
prefix = os.path.join(WORK, "root")
run(["dpkg-deb", "-x", deb, prefix])
usr = os.path.join(prefix, "usr")
out = run([os.path.join(usr, "bin", "vrsph"), "--version"])
assert out.startswith(f"vrsph {version} "), out
env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
env["PYTHONPATH"] = os.path.join(usr, "lib", "python3", "dist-packages")
out = run(["/usr/bin/python3", "-c", "import vrsph; print(vrsph.__file__, vrsph.__version__)"], env=env, cwd=WORK)
assert out.startswith(usr) and out.split()[1] == version, out
build = os.path.join(WORK, "consumer")
run(["cmake", "-S", CONSUMER, "-B", build, f"-DCMAKE_PREFIX_PATH={usr}", "-DCMAKE_BUILD_TYPE=Release"])
run(["cmake", "--build", build])
for program in ("consumer", "consumer_bvp"):
    print(run([os.path.join(build, program)], cwd=build).strip())
print(f"{os.path.basename(deb)}: {os.path.getsize(deb) / 1e6:.1f} MB; {depends.strip()}")
