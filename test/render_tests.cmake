# Renderer tests (issue 4): headless, no ROS master, GoogleTest via catkin_add_gtest.
# PNGs of every test scene go to ${CMAKE_BINARY_DIR}/test_images/ for people to look at.
set(PBF_RENDER_TEST_DIR ${CMAKE_CURRENT_LIST_DIR}/render)
set(PBF_TEST_IMAGE_DIR ${CMAKE_BINARY_DIR}/test_images)
file(MAKE_DIRECTORY ${PBF_TEST_IMAGE_DIR})

foreach(test_name render_backend_tests render_camera_tests render_ball_tests render_slab_tests)
  string(REPLACE "render_" "" stem ${test_name})
  string(REPLACE "_tests" "" stem ${stem})
  catkin_add_gtest(${test_name} ${PBF_RENDER_TEST_DIR}/test_${stem}.cpp)
  if(TARGET ${test_name})
    target_link_libraries(${test_name} pbf_render gtest_main)
    target_compile_definitions(${test_name} PRIVATE
      PBF_SHADER_SOURCE_DIR="${PBF_SHADER_SOURCE_DIR}"
      PBF_TEST_IMAGE_DIR="${PBF_TEST_IMAGE_DIR}")
  endif()
endforeach()
