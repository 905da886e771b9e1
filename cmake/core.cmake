# pbf_core: the solver. Plain C++17 + Eigen + OpenMP + yaml-cpp; no ROS, no GL.

# The hot neighbour sums, compiled twice: for the build's target and for x86-64-v3 (AVX2 +
# FMA); NeighborSumsDispatch.cpp picks one at run time (see NeighborSums.h).
foreach(variant base v3)
  add_library(pbf_neighbor_sums_${variant} OBJECT src/core/NeighborSums.cpp)
  target_link_libraries(pbf_neighbor_sums_${variant} PRIVATE OpenMP::OpenMP_CXX)
  target_compile_options(pbf_neighbor_sums_${variant} PRIVATE -fno-trapping-math)
  target_compile_definitions(pbf_neighbor_sums_${variant} PRIVATE
    PBF_NEIGHBOR_SUMS_NS=neighbor_sums_${variant})
  set_target_properties(pbf_neighbor_sums_${variant} PROPERTIES POSITION_INDEPENDENT_CODE ON)
endforeach()
# use_gather: gather instructions for the neighbours' positions (GCC's generic tuning builds
# each from scalar loads; see NeighborSums.cpp).
if(CMAKE_SYSTEM_PROCESSOR MATCHES "x86_64|AMD64")
  target_compile_options(pbf_neighbor_sums_v3 PRIVATE -march=x86-64-v3 -mtune-ctrl=use_gather)
endif()

add_library(pbf_core
  src/core/NeighborGrid.cpp
  src/core/CandidateFilter.cpp
  src/core/PbfSolver.cpp
  src/core/SolverNeighbors.cpp
  src/core/JacobiSolve.cpp
  src/core/ConstraintPasses.cpp
  src/core/GaussSeidelSweep.cpp
  src/core/BlockColours.cpp
  src/core/ChebyshevAcceleration.cpp
  src/core/VelocityPasses.cpp
  src/core/DensityMeasurement.cpp
  src/core/StepGuards.cpp
  src/core/NeighborSumsDispatch.cpp
  $<TARGET_OBJECTS:pbf_neighbor_sums_base>
  $<TARGET_OBJECTS:pbf_neighbor_sums_v3>
  src/core/WrenchTracking.cpp
  src/core/SolidWrench.cpp
  src/core/RigidBody.cpp
  src/core/FloatingBodies.cpp
  src/core/ParticleChanges.cpp
  src/core/FluidReach.cpp
  src/core/FluidSources.cpp
  src/core/SolverParams.cpp
  src/core/Scene.cpp
  src/core/Metrics.cpp
  src/core/FreeSurfaceHeight.cpp
  src/core/Obstacle.cpp
  src/core/TriangleMesh.cpp
  src/core/SignedDistanceGrid.cpp
  src/core/Boundaries.cpp
  src/core/FreeSurfaceLend.cpp
  src/core/NewParticleLends.cpp
  src/core/LatticeBoundary.cpp)
target_include_directories(pbf_core PUBLIC include)
target_link_libraries(pbf_core PUBLIC Eigen3::Eigen OpenMP::OpenMP_CXX yaml-cpp)
set_target_properties(pbf_core PROPERTIES POSITION_INDEPENDENT_CODE ON)
