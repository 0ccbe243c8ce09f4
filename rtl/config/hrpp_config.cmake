# The hardware's configurations and latencies (rtl/config/hrpp_configs.json, rtl/config/README.md)
# for the build, at configure time: rtl/config/hrpp_config.py writes
#   ${HRPP_GENERATED_DIR}/hrpp/rtl_config_data.h  the C++ table (model/include/hrpp/hardware/rtl_config.h)
#   ${HRPP_GENERATED_DIR}/hrpp_configs.cmake      HRPP_CONFIGS and each HRPP_CFG_<name>'s
#                                                 Verilator -G flags (tb/CMakeLists.txt)
# Editing the JSON file, the generator or its loader (pyhrpp/rtl_config.py) reconfigures the
# build.
find_package(Python3 COMPONENTS Interpreter REQUIRED)
set(HRPP_CONFIG_JSON ${CMAKE_CURRENT_LIST_DIR}/hrpp_configs.json)
set(HRPP_CONFIG_GEN ${CMAKE_CURRENT_LIST_DIR}/hrpp_config.py)
get_filename_component(HRPP_PYHRPP_DIR ${CMAKE_CURRENT_LIST_DIR}/../../pyhrpp ABSOLUTE)
set(HRPP_GENERATED_DIR ${PROJECT_BINARY_DIR}/generated)
execute_process(
  COMMAND ${Python3_EXECUTABLE} ${HRPP_CONFIG_GEN} --json ${HRPP_CONFIG_JSON}
          --cpp ${HRPP_GENERATED_DIR}/hrpp/rtl_config_data.h
          --cmake ${HRPP_GENERATED_DIR}/hrpp_configs.cmake
  RESULT_VARIABLE HRPP_CONFIG_RC ERROR_VARIABLE HRPP_CONFIG_ERR)
if(NOT HRPP_CONFIG_RC EQUAL 0)
  message(FATAL_ERROR "rtl/config/hrpp_config.py failed (${HRPP_CONFIG_RC}): ${HRPP_CONFIG_ERR}")
endif()
set_property(DIRECTORY ${PROJECT_SOURCE_DIR} APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS
             ${HRPP_CONFIG_JSON} ${HRPP_CONFIG_GEN}
             ${HRPP_PYHRPP_DIR}/rtl_config.py ${HRPP_PYHRPP_DIR}/files.py)
include(${HRPP_GENERATED_DIR}/hrpp_configs.cmake)
include_directories(${HRPP_GENERATED_DIR})
