#!/bin/sh
# Compiler launcher of tb_hrpp (tb/CMakeLists.txt):  verilated_cxx.sh VCXX CXX ARGS...
# Compiles Verilator's generated model classes (a source under a Vhrpp_<config>.dir/ directory)
# with VCXX (clang++ when CMake found it), and every other file (the testbench, the cycle model,
# Verilator's runtime) with the project's compiler CXX, as CMake asked.
# Why: the generated evaluation code is a few very long straight-line functions; clang++'s code
# for them has 13% fewer instructions than g++'s, and the co-simulation runs about 9% faster
# (docs/results.md, "Performance"; cmake -DHRPP_VERILATED_CXX=OFF builds it with g++). Both
# compilers use libstdc++ and the same ABI, so the objects link together.
vcxx=$1
cxx=$2
shift 2
src=
prev=
for a in "$@"; do
  [ "$prev" = "-c" ] && src=$a
  prev=$a
done
# Verilator's generated code uses | and & on booleans on purpose; clang warns about each.
case "$src" in
  */Vhrpp_*.dir/Vhrpp_*.cpp) exec "$vcxx" "$@" -Wno-bitwise-instead-of-logical ;;
esac
exec "$cxx" "$@"
