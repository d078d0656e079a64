# CMake generated Testfile for 
# Source directory: /work/main/tests
# Build directory: /work/main/build/tests
# 
# This file includes the relevant testing commands required for 
# testing this directory and lists subdirectories to be tested as well.
include("/work/main/build/tests/test_bvh[1]_include.cmake")
include("/work/main/build/tests/test_obb[1]_include.cmake")
include("/work/main/build/tests/test_scene_validation[1]_include.cmake")
include("/work/main/build/tests/test_cross_backend[1]_include.cmake")
