# Command-line tools on the ROS-free core.
add_executable(pbf_run src/tools/run_scene.cpp)
target_link_libraries(pbf_run pbf_core)
target_compile_definitions(pbf_run PRIVATE PBF_SOURCE_DIR="${CMAKE_CURRENT_SOURCE_DIR}")

# Google Benchmark of one step (README performance table). Optional: only this developer
# tool needs it, so the node and its libraries build without it.
find_package(benchmark QUIET)
if(benchmark_FOUND)
  add_executable(pbf_step_benchmark src/tools/step_benchmark.cpp)
  target_link_libraries(pbf_step_benchmark pbf_core benchmark::benchmark)
  target_compile_definitions(pbf_step_benchmark PRIVATE PBF_SOURCE_DIR="${CMAKE_CURRENT_SOURCE_DIR}")
else()
  message(STATUS "pbf_ros: Google Benchmark not found (Debian: libbenchmark-dev); "
                 "pbf_step_benchmark is not built")
endif()

# The fluid's force on a held solid against Archimedes at a chosen resolution (README).
add_executable(pbf_hydrostatic_forces src/tools/hydrostatic_forces.cpp)
target_link_libraries(pbf_hydrostatic_forces pbf_core)
