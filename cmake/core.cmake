# pbf_core: the solver. Plain C++17 + Eigen + OpenMP + yaml-cpp; no ROS, no GL.
add_library(pbf_core
  src/core/NeighborGrid.cpp
  src/core/PbfSolver.cpp
  src/core/SolverNeighbors.cpp
  src/core/ConstraintPasses.cpp
  src/core/VelocityPasses.cpp
  src/core/StepGuards.cpp
  src/core/NeighborSums.cpp
  src/core/WrenchTracking.cpp
  src/core/SolidWrench.cpp
  src/core/RigidBody.cpp
  src/core/FloatingBodies.cpp
  src/core/SolverParams.cpp
  src/core/Scene.cpp
  src/core/Metrics.cpp
  src/core/Obstacle.cpp
  src/core/TriangleMesh.cpp
  src/core/SignedDistanceGrid.cpp
  src/core/Boundaries.cpp
  src/core/LatticeBoundary.cpp)
target_include_directories(pbf_core PUBLIC include)
target_link_libraries(pbf_core PUBLIC Eigen3::Eigen OpenMP::OpenMP_CXX yaml-cpp)
set_target_properties(pbf_core PROPERTIES POSITION_INDEPENDENT_CODE ON)
