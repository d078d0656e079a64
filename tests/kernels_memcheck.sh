#!/bin/sh
# ctests kernels_memcheck_<type>: the kernels' C++ build reads no uninitialised value and
# touches no memory it should not. One cross-backend case per ctest (capsules, which the
# cpu tests four at a time in its own vector code, and curves, the longest search of the
# kernels; each instanced beside a mesh, robust and fast, every method) on the cpu backend
# alone, under valgrind's memcheck: the two types that carry most of the code, as two
# ctests that run side by side.
# Only valgrind's verdict decides: the case's own comparison with the long-double oracle
# may differ under valgrind, which computes x87 long doubles to 64 bits only (the same
# case passes in the suite proper), so a gtest failure (exit 1) is not this test's.
# usage: kernels_memcheck.sh VALGRIND TEST_BINARY TYPE (capsule, curve: the case's parameter)
set -u
valgrind=$1 binary=$2 type=$3
MASQ_TEST_BACKENDS=cpu MASQ_CPU_THREADS=2 "$valgrind" --tool=memcheck --error-exitcode=99 --track-origins=yes \
  --quiet "$binary" --gtest_brief=1 --gtest_filter="Types/EveryPrimitive.InstancedWithMeshRobustAndFast/$type"
rc=$?
case $rc in
  0|1) echo "kernels_memcheck: no memcheck error (the case exited $rc)"; exit 0 ;;
  99) echo "kernels_memcheck: memcheck found errors (above)" >&2; exit 1 ;;
  *) echo "kernels_memcheck: the case ended with status $rc under valgrind" >&2; exit 1 ;;
esac
