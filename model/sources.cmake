# The sources of the model's three libraries, relative to the repository root. Included by the
# main build (CMakeLists.txt) and by the fuzz build (fuzz/CMakeLists.txt).
#   hrpp_model      the core: scenes, BVH, traversal, workloads, ray streams, hash, predictor,
#                   cycle model, cost model and the RTL's update delay. Links neither Embree nor
#                   an image writer.
#   hrpp_reference  the cross-check against Embree (links Embree).
#   hrpp_report     pictures (PNG writing with stb) and the speculative-image error, which
#                   writes pictures.
set(HRPP_MODEL_SOURCES
  model/src/atomic_file.cc
  model/src/bvh.cc
  model/src/cost_model.cc
  model/src/cycle_model.cc
  model/src/engine_side.cc
  model/src/hash.cc
  model/src/pred_table.cc
  model/src/predictor.cc
  model/src/ray.cc
  model/src/ray_generator.cc
  model/src/ray_stream.cc
  model/src/referee.cc
  model/src/rtl_update_delay.cc
  model/src/sampling.cc
  model/src/scene.cc
  model/src/tiled_predictor.cc
  model/src/traverse.cc
  model/src/workload_options.cc
)
set(HRPP_REFERENCE_SOURCES
  model/src/crosscheck.cc
  model/src/embree_ref.cc
)
set(HRPP_REPORT_SOURCES
  model/src/render.cc
  model/src/spec_image.cc
)
