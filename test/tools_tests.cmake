# Tool tests (issue 5): the reduced stress matrix of pbf_stress as a gtest (< ~60 s).
catkin_add_gtest(test_stress_reduced test/tools/test_stress_reduced.cpp)
if(TARGET test_stress_reduced)
  target_link_libraries(test_stress_reduced pbf_bench_support pbf_core gtest_main)
  target_compile_definitions(test_stress_reduced PRIVATE PBF_SOURCE_DIR="${CMAKE_CURRENT_SOURCE_DIR}")
endif()
# Under load (2 shared cores) OpenMP's default spin-waiting makes small-N steps ~20x slower;
# sleep-waiting keeps the test fast and changes no result.
if(TEST _ctest_pbf_ros_gtest_test_stress_reduced)
  set_tests_properties(_ctest_pbf_ros_gtest_test_stress_reduced PROPERTIES ENVIRONMENT "OMP_WAIT_POLICY=passive")
endif()

# The dam-break study's resolutions hold the same water (no lattice gaps).
catkin_add_gtest(test_dam_break_study test/tools/test_dam_break_study.cpp)
if(TARGET test_dam_break_study)
  target_link_libraries(test_dam_break_study pbf_bench_support pbf_core gtest_main)
endif()

# The tank study's measures of the layers along the walls, on a lattice where they are known.
catkin_add_gtest(test_tank_measures test/tools/test_tank_measures.cpp)
if(TARGET test_tank_measures)
  target_link_libraries(test_tank_measures pbf_bench_support pbf_core gtest_main)
endif()

# The accelerated solve (chebyshev_rho 0.95, warm start, doubled step) through the stress
# cases it once failed (~2 s).
catkin_add_gtest(test_stress_accelerated test/tools/test_stress_accelerated.cpp)
if(TARGET test_stress_accelerated)
  target_link_libraries(test_stress_accelerated pbf_bench_support pbf_core gtest_main)
endif()
if(TEST _ctest_pbf_ros_gtest_test_stress_accelerated)
  set_tests_properties(_ctest_pbf_ros_gtest_test_stress_accelerated PROPERTIES ENVIRONMENT "OMP_WAIT_POLICY=passive")
endif()

# The dam-break study's surge-front measures (slab and sliding window) on known layouts.
catkin_add_gtest(test_surge_front test/tools/test_surge_front.cpp)
if(TARGET test_surge_front)
  target_link_libraries(test_surge_front pbf_bench_support pbf_core gtest_main)
endif()

# The scaling study's protocol, and pbf_bench's --set reaching it.
catkin_add_gtest(test_scaling_study test/tools/test_scaling_study.cpp)
if(TARGET test_scaling_study)
  target_link_libraries(test_scaling_study pbf_bench_support pbf_core gtest_main)
endif()

# pbf_run counts a scene before it allocates it and names a bad number (session 36: a
# --spacing of 1e-5 grew by 3 GB a second; 0, NaN and negative spacings were ignored).
add_test(NAME test_pbf_run_refuses_a_spacing_bomb
         COMMAND ${CATKIN_DEVEL_PREFIX}/lib/pbf_ros/pbf_run hydrostatic_tank --spacing 1e-5)
set_tests_properties(test_pbf_run_refuses_a_spacing_bomb PROPERTIES TIMEOUT 30
                     PASS_REGULAR_EXPRESSION "lattice cells; expected at most 5e8")
add_test(NAME test_pbf_run_refuses_a_spacing_over_max_particles
         COMMAND ${CATKIN_DEVEL_PREFIX}/lib/pbf_ros/pbf_run hydrostatic_tank --spacing 0.003)
set_tests_properties(test_pbf_run_refuses_a_spacing_over_max_particles PROPERTIES TIMEOUT 30
                     PASS_REGULAR_EXPRESSION "needs more than 1000000 particles \\(--max-particles\\)")
add_test(NAME test_pbf_run_names_a_bad_number
         COMMAND ${CATKIN_DEVEL_PREFIX}/lib/pbf_ros/pbf_run hydrostatic_tank --spacing nan)
set_tests_properties(test_pbf_run_names_a_bad_number PROPERTIES TIMEOUT 30
                     PASS_REGULAR_EXPRESSION "--spacing expects a finite number > 0, got 'nan'")

# The other tools name a bad argument too (session 36: an abort, NaN printed with exit 0, a
# traceback, a 24 GB allocation).
add_test(NAME test_hydrostatic_forces_names_a_bad_argument
         COMMAND ${CATKIN_DEVEL_PREFIX}/lib/pbf_ros/pbf_hydrostatic_forces sphere 0.02 0.3 0.24 nan)
set_tests_properties(test_hydrostatic_forces_names_a_bad_argument PROPERTIES TIMEOUT 30
                     PASS_REGULAR_EXPRESSION "SIZE expects a finite number > 0, got 'nan'")
add_test(NAME test_render_bench_bounds_its_counts
         COMMAND ${CATKIN_DEVEL_PREFIX}/lib/pbf_ros/pbf_render_bench --counts 2000000000)
set_tests_properties(test_render_bench_bounds_its_counts PROPERTIES TIMEOUT 30
                     PASS_REGULAR_EXPRESSION "--counts expects an integer in \\[1, 1000000\\], got '2000000000'")
add_test(NAME test_measure_rtf_names_a_bad_duration
         COMMAND /usr/bin/python3 ${CMAKE_CURRENT_SOURCE_DIR}/scripts/measure_rtf.py nan)
set_tests_properties(test_measure_rtf_names_a_bad_duration PROPERTIES TIMEOUT 30
                     ENVIRONMENT "PYTHONPATH=${CATKIN_DEVEL_PREFIX}/lib/python3/dist-packages"
                     PASS_REGULAR_EXPRESSION "seconds must be a finite number > 0, got nan")
