# SPDX-License-Identifier: BSD-3-Clause
# Run first by `cmake --install` (CMakeLists.txt): an install prefix this user cannot write to
# stops here with what to do instead, not half way with CMake's "cannot copy file".
set(_target "$ENV{DESTDIR}${CMAKE_INSTALL_PREFIX}")
set(_dir "${_target}")
while(NOT EXISTS "${_dir}")  # the first existing directory on the way
  get_filename_component(_parent "${_dir}" DIRECTORY)
  if(_parent STREQUAL _dir)
    break()
  endif()
  set(_dir "${_parent}")
endwhile()
execute_process(COMMAND test -w "${_dir}" RESULT_VARIABLE _not_writable)
if(_not_writable)
  message(FATAL_ERROR "vrsph: cannot install into ${_target}: ${_dir} is not writable by this user. Install as "
                      "root (sudo cmake --install <build>), or into a prefix you own: cmake --install <build> --prefix "
                      "$ENV{HOME}/.local (then find_package finds it with -DCMAKE_PREFIX_PATH=$ENV{HOME}/.local and "
                      "Python with PYTHONPATH=$ENV{HOME}/.local/lib/python3/dist-packages), or use the Debian package "
                      "(cpack -G DEB) or pip (python3 -m pip install --user --no-build-isolation .)")
endif()
