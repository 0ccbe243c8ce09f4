# The sources of the model's three libraries, relative to the repository root. Included by the
# main build (CMakeLists.txt) and by the fuzz build (fuzz/CMakeLists.txt).
#   hrpp_model      the core: scenes, BVH, traversal, workloads, ray streams, hash, predictor,
#                   cycle model, cost model and the RTL's update delay. Links Embree (and TBB)
#                   only for MICRO 2021's BVH builder (bvh_micro21.cc), no image writer.
#   hrpp_reference  the cross-check and the exactness check against Embree (links Embree).
#   hrpp_report     pictures (PNG writing with stb) and the speculative-image error, which
#                   writes pictures.
set(HRPP_MODEL_SOURCES
  model/src/util/atomic_file.cc
  model/src/trace/bvh.cc
  model/src/trace/bvh_micro21.cc
  model/src/timing/cost_model.cc
  model/src/hardware/cycle_model.cc
  model/src/hardware/cycle_model_lanes.cc
  model/src/hardware/lane_model.cc
  model/src/predictor/engine_side.cc
  model/src/predictor/hash.cc
  model/src/predictor/pred_table.cc
  model/src/predictor/predictor.cc
  model/src/predictor/presets.cc
  model/src/trace/ray.cc
  model/src/workload/ray_generator.cc
  model/src/workload/ray_stream.cc
  model/src/trace/referee.cc
  model/src/hardware/rtl_update_delay.cc
  model/src/workload/sampling.cc
  model/src/scene/scene.cc
  model/src/predictor/tiled_predictor.cc
  model/src/trace/traverse.cc
  model/src/workload/workload_options.cc
  model/src/sim/gpu_config.cc
  model/src/sim/memory.cc
  model/src/sim/simulator.cc
  model/src/sim/unit_predictor.cc
)
set(HRPP_REFERENCE_SOURCES
  model/src/reference/crosscheck.cc
  model/src/reference/embree_ref.cc
  model/src/reference/exactness.cc
)
set(HRPP_REPORT_SOURCES
  model/src/report/render.cc
  model/src/report/spec_image.cc
)
# MICRO 2021's split callback rounds every float operation on its own, as their x86-64 build did
# (no FMA): no contraction into fused multiply-adds.
set_source_files_properties(${CMAKE_CURRENT_LIST_DIR}/src/trace/bvh_micro21.cc
                            PROPERTIES COMPILE_OPTIONS -ffp-contract=off)
