# Validation and stress tools (issue 5): pbf_bench (accuracy, Pareto, scaling) and
# pbf_stress (hostile-case matrix). No ROS; they link the core only. The helpers in
# src/tools/bench/ are a small static library shared with the reduced stress gtest.
add_library(pbf_bench_support STATIC
  src/tools/bench/BenchScenes.cpp
  src/tools/bench/SurfaceMetrics.cpp
  src/tools/bench/MartinMoyce.cpp
  src/tools/bench/SceneRun.cpp
  src/tools/bench/DamBreak.cpp
  src/tools/bench/Hydrostatic.cpp
  src/tools/bench/DamBreakStudy.cpp
  src/tools/bench/SettingsSweep.cpp
  src/tools/bench/ScalingStudy.cpp
  src/tools/bench/WarmStartStudy.cpp
  src/tools/bench/TankStudy.cpp
  src/tools/bench/StressCases.cpp
  src/tools/bench/EnergyBound.cpp)
target_include_directories(pbf_bench_support PUBLIC ${CMAKE_CURRENT_SOURCE_DIR}/src/tools)
target_link_libraries(pbf_bench_support PUBLIC pbf_core)
target_compile_definitions(pbf_bench_support PUBLIC PBF_SOURCE_DIR="${CMAKE_CURRENT_SOURCE_DIR}")

add_executable(pbf_bench src/tools/pbf_bench.cpp)
target_link_libraries(pbf_bench pbf_bench_support)

add_executable(pbf_stress src/tools/pbf_stress.cpp)
target_link_libraries(pbf_stress pbf_bench_support)
