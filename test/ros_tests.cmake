# ROS layer tests, run by ctest.
#  - test_ros_units: GoogleTest, no master: the plain conversion / pacing / health functions
#    (and the render camera parameters, CameraInfo and surface image conversions).
#  - rostest launch files: pbf_node on a small fluid (particle_spacing 0.05 -> ~1.3k
#    particles) with Python test nodes, plus rostest's hztest for the cloud rate.
find_package(rostest REQUIRED)

catkin_add_gtest(test_ros_units
  test/ros/test_camera_info_conversion.cpp
  test/ros/test_cloud_conversion.cpp
  test/ros/test_params_conversion.cpp
  test/ros/test_real_time_pacer.cpp
  test/ros/test_render_camera_params.cpp
  test/ros/test_scene_markers.cpp
  test/ros/test_snapshot_buffer.cpp
  test/ros/test_stats_and_health.cpp
  test/ros/test_wrench_targets.cpp)
if(TARGET test_ros_units)
  # catkin links gtest but not its main().
  target_link_libraries(test_ros_units pbf_ros_node gtest_main)
endif()

add_rostest(test/node_interface.test DEPENDENCIES pbf_node)
add_rostest(test/particles_rate.test DEPENDENCIES pbf_node)
add_rostest(test/node_control.test DEPENDENCIES pbf_node)
add_rostest(test/sim_clock.test DEPENDENCIES pbf_node)
add_rostest(test/attached_frames.test DEPENDENCIES pbf_node)
add_rostest(test/missing_frame.test DEPENDENCIES pbf_node)
add_rostest(test/surface_topics.test DEPENDENCIES pbf_node)
add_rostest(test/surface_no_gl.test DEPENDENCIES pbf_node)
add_rostest(test/node_lifecycle.test DEPENDENCIES pbf_node)
add_rostest(test/hostile_input.test DEPENDENCIES pbf_node)
add_rostest(test/reset_moved_frame.test DEPENDENCIES pbf_node)
add_rostest(test/robot_solids.test DEPENDENCIES pbf_node)
add_rostest(test/floating_bodies.test DEPENDENCIES pbf_node)

# Robots as solids (pbf_robots): URDF strings and the shipped arm's meshes, no master.
catkin_add_gtest(test_ros_urdf_solids test/ros/test_urdf_solids.cpp)
if(TARGET test_ros_urdf_solids)
  target_link_libraries(test_ros_urdf_solids pbf_robots gtest_main)
  target_compile_definitions(test_ros_urdf_solids PRIVATE PBF_SOURCE_DIR="${CMAKE_CURRENT_SOURCE_DIR}")
endif()
