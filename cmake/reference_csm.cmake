# The reference PLICP implementation (Censi's CSM, LGPL-3) for the side-by-side benchmark
# bench/plicp_vs_csm_bench.cpp. Its sources stay where they are (../shared/reference/csm by
# default, never copied into this repository) and are compiled into this build tree as the
# static library reference_csm. Without the sources or GSL (libgsl-dev) the benchmark is not
# built and a status line says why. Sets ODOMETRY_CALIBRATION_HAVE_CSM.
set(ODOMETRY_CALIBRATION_CSM_DIR "${PROJECT_SOURCE_DIR}/../shared/reference/csm" CACHE PATH
    "CSM's source folder (with sm/); the PLICP side-by-side benchmark is skipped without it")
set(ODOMETRY_CALIBRATION_HAVE_CSM OFF)
set(csm_sm "${ODOMETRY_CALIBRATION_CSM_DIR}/sm")
find_package(GSL QUIET)
if(NOT EXISTS "${csm_sm}/csm/algos.h")
  message(STATUS "reference CSM: no sources at ${ODOMETRY_CALIBRATION_CSM_DIR}: "
                 "bench_plicp_vs_csm not built")
  return()
endif()
if(NOT GSL_FOUND)
  message(STATUS "reference CSM: GSL not found (libgsl-dev): bench_plicp_vs_csm not built")
  return()
endif()
enable_language(C)
# What CSM's own build compiles into csm-static (sm/CMakeLists.txt), without the Cairo drawing.
set(csm_sources)
foreach(source
    csm/clustering.c csm/gpm/gpm.c csm/icp/icp.c csm/icp/icp_corr_dumb.c
    csm/icp/icp_corr_tricks.c csm/icp/icp_covariance.c csm/icp/icp_loop.c csm/icp/icp_outliers.c
    csm/icp/icp_debug.c csm/mbicp/mbicp_interface.c csm/mbicp/MbICP.c csm/mbicp/calcul.c
    csm/mbicp/percolate.c csm/mbicp/sp_matrix.c csm/hsm/hsm.c csm/hsm/hsm_interface.c
    csm/json_journal.c csm/laser_data.c csm/laser_data_carmen.c csm/laser_data_fisher.c
    csm/laser_data_json.c csm/laser_data_load.c csm/laser_data_drawing.c csm/laser_data_bbox.c
    csm/logging.c csm/math_utils.c csm/math_utils_gsl.c csm/orientation.c csm/sm_options.c
    csm/utils.c lib/egsl/egsl.c lib/egsl/egsl_conversions.c lib/egsl/egsl_misc.c
    lib/egsl/egsl_ops.c lib/gpc/gpc.c lib/gpc/gpc_utils.c lib/json-c/arraylist.c
    lib/json-c/debug.c lib/json-c/JSON_checker.c lib/json-c/json_more_utils.c
    lib/json-c/json_object.c lib/json-c/json_tokener.c lib/json-c/json_util.c
    lib/json-c/linkhash.c lib/json-c/printbuf.c lib/options/options.c
    lib/options/options_interface.c)
  list(APPEND csm_sources "${csm_sm}/${source}")
endforeach()
# json-c's config.h: what glibc on Debian has (its own build probes the same headers/functions).
foreach(have HAVE_FCNTL_H HAVE_INTTYPES_H HAVE_LIMITS_H HAVE_MALLOC HAVE_MEMORY_H HAVE_OPEN
        HAVE_REALLOC HAVE_STDARG_H HAVE_STDINT_H HAVE_STDLIB_H HAVE_STRERROR HAVE_STRINGS_H
        HAVE_STRING_H HAVE_STRNCASECMP HAVE_STRNDUP HAVE_SYSLOG_H HAVE_SYS_PARAM_H
        HAVE_SYS_STAT_H HAVE_SYS_TYPES_H HAVE_UNISTD_H HAVE_VASPRINTF HAVE_VPRINTF
        HAVE_VSNPRINTF HAVE_VSYSLOG)
  set(${have} 1)
endforeach()
set(HAVE_DOPRNT 0)
configure_file("${csm_sm}/lib/json-c/config.h.cmake" "${CMAKE_BINARY_DIR}/reference_csm/config.h")
add_library(reference_csm STATIC ${csm_sources})
target_include_directories(reference_csm SYSTEM PUBLIC "${csm_sm}" "${csm_sm}/lib"
                           "${CMAKE_BINARY_DIR}/reference_csm")
# CSM's recipe: -O2 with _GNU_SOURCE (json-c's strdup); its warnings are not ours to fix.
target_compile_options(reference_csm PRIVATE -O2 -w)
target_compile_definitions(reference_csm PRIVATE _GNU_SOURCE LINUX)
target_link_libraries(reference_csm PUBLIC GSL::gsl m)
set(ODOMETRY_CALIBRATION_HAVE_CSM ON)
