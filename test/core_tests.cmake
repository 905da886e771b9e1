# Core unit tests: GoogleTest, no ROS master. Built by `make tests`, run by ctest.
set(PBF_CORE_TESTS kernels neighbor_grid solver_physics solver_robustness scene scene_limits
    boundaries calibration obstacle_shapes signed_distance_grid solids_in_fluid
    solid_wrenches floating_bodies fluid_sources far_solids warm_start gauss_seidel step_allocations
    neighbor_sums free_surface_lend)
foreach(t ${PBF_CORE_TESTS})
  catkin_add_gtest(test_core_${t} test/core/test_${t}.cpp)
  target_link_libraries(test_core_${t} pbf_core gtest_main)
  target_compile_definitions(test_core_${t} PRIVATE PBF_SOURCE_DIR="${CMAKE_CURRENT_SOURCE_DIR}")
endforeach()
# The candidate filter's and the neighbour sums' two builds, the Gauss-Seidel order's
# blocks and the free surface's lend table are private to pbf_core; their tests reach them.
target_include_directories(test_core_neighbor_grid PRIVATE src/core)
target_include_directories(test_core_neighbor_sums PRIVATE src/core)
target_include_directories(test_core_gauss_seidel PRIVATE src/core)
target_include_directories(test_core_free_surface_lend PRIVATE src/core)
target_include_directories(test_core_solver_physics PRIVATE src/core)  # the lend in the transcription
