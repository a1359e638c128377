# Finding Debian 12's ROS 1 packages (issue 32: server/rosbag, clients/ros). Their CMake configs are catkin's: they
# run Python templates with the project's Python3 interpreter (a pyenv one lacks Debian's catkin / ament modules) and
# set BUILD_SHARED_LIBS. anchordb_find_ros1(FOUND pkg...) puts Debian's Python modules on PYTHONPATH for these
# find_package calls only, restores BUILD_SHARED_LIBS, and sets FOUND to TRUE when every package was found (a macro:
# the packages' variables, <pkg>_INCLUDE_DIRS and <pkg>_LIBRARIES, land in the caller's scope).
set(ANCHORDB_ROS_PYTHON "/usr/bin/python3" CACHE FILEPATH
    "Debian's Python, with rosbag, genpy, genmsg and gencpp (message generation and the ROS tests)")
macro(anchordb_find_ros1 found_var)
  set(_anchordb_pythonpath_before "$ENV{PYTHONPATH}")
  set(ENV{PYTHONPATH} "/usr/lib/python3/dist-packages:$ENV{PYTHONPATH}")
  set(_anchordb_shared_before "${BUILD_SHARED_LIBS}")
  set(${found_var} TRUE)
  foreach(_anchordb_pkg ${ARGN})
    find_package(${_anchordb_pkg} CONFIG QUIET)
    if(NOT ${_anchordb_pkg}_FOUND)
      set(${found_var} FALSE)
    endif()
  endforeach()
  set(BUILD_SHARED_LIBS "${_anchordb_shared_before}")
  set(ENV{PYTHONPATH} "${_anchordb_pythonpath_before}")
endmacro()
