# ROS layer tests, run by ctest.
#  - test_ros_units: GoogleTest, no master: the plain conversion / pacing / health functions
#    (and the render camera parameters, CameraInfo and surface image conversions).
#  - rostest launch files: pbf_node on a small fluid (particle_spacing 0.05 -> ~1.3k
#    particles) with Python test nodes, plus rostest's hztest for the cloud rate.
find_package(rostest REQUIRED)

catkin_add_gtest(test_ros_units
  test/ros/test_camera_info_conversion.cpp
  test/ros/test_cloud_conversion.cpp
  test/ros/test_node_params.cpp
  test/ros/test_obstacle_mover.cpp
  test/ros/test_params_conversion.cpp
  test/ros/test_real_time_pacer.cpp
  test/ros/test_ros_clock_jumps.cpp
  test/ros/test_render_camera_params.cpp
  test/ros/test_scene_markers.cpp
  test/ros/test_snapshot_buffer.cpp
  test/ros/test_stats_and_health.cpp
  test/ros/test_tf_attachments.cpp
  test/ros/test_tf_stamp_gate.cpp
  test/ros/test_wrench_targets.cpp
  test/ros/test_topic_rate_diagnostic.cpp)  # last: it sets simulated time for the process
if(TARGET test_ros_units)
  # catkin links gtest but not its main().
  target_link_libraries(test_ros_units pbf_ros_node gtest_main)
endif()

add_rostest(test/node_interface.test DEPENDENCIES pbf_node)
add_rostest(test/particles_rate.test DEPENDENCIES pbf_node)
add_rostest(test/node_control.test DEPENDENCIES pbf_node)
add_rostest(test/sim_clock.test DEPENDENCIES pbf_node)
add_rostest(test/late_clock.test DEPENDENCIES pbf_node)
add_rostest(test/external_clock.test DEPENDENCIES pbf_node)
add_rostest(test/attached_frames.test DEPENDENCIES pbf_node)
add_rostest(test/missing_frame.test DEPENDENCIES pbf_node)
add_rostest(test/surface_topics.test DEPENDENCIES pbf_node)
add_rostest(test/surface_no_gl.test DEPENDENCIES pbf_node)
add_rostest(test/node_lifecycle.test DEPENDENCIES pbf_node)
add_rostest(test/hostile_input.test DEPENDENCIES pbf_node)
add_rostest(test/reset_moved_frame.test DEPENDENCIES pbf_node)
add_rostest(test/robot_solids.test DEPENDENCIES pbf_node)
add_rostest(test/floating_bodies.test DEPENDENCIES pbf_node)
add_rostest(test/sources_and_drains.test DEPENDENCIES pbf_node)
add_rostest(test/robot_pouring.test DEPENDENCIES pbf_node)
# The pouring arm's start pose reaches a late tf listener before /clock runs (no fluid node).
add_rostest(test/pouring_startup_tf.test)
add_rostest(test/obstacle_mover.test DEPENDENCIES pbf_node)
add_rostest(test/paused_tf.test DEPENDENCIES pbf_node)
# The nodelet in a manager beside depth_image_proc's point_cloud_xyzrgb.
add_rostest(test/fluid_nodelet.test DEPENDENCIES pbf_fluid_nodelet)

# The launch files parse and name packages and executables that exist.
find_package(roslaunch REQUIRED)
roslaunch_add_file_check(launch USE_TEST_DEPENDENCIES)

# scripts/rviz_for_node.py fits the rviz config to a node (no master).
add_test(NAME test_rviz_for_node
         COMMAND /usr/bin/python3 ${CMAKE_CURRENT_SOURCE_DIR}/test/ros/test_rviz_for_node.py)

# The install space alone runs fluid.launch (cmake --install into a temporary prefix).
add_test(NAME test_install_space
         COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/test/install_space.sh ${CMAKE_BINARY_DIR})
set_tests_properties(test_install_space PROPERTIES TIMEOUT 120)

# Robots as solids (pbf_robots): URDF strings and the shipped arm's meshes, no master.
catkin_add_gtest(test_ros_urdf_solids test/ros/test_urdf_solids.cpp)
if(TARGET test_ros_urdf_solids)
  target_link_libraries(test_ros_urdf_solids pbf_robots gtest_main)
  target_compile_definitions(test_ros_urdf_solids PRIVATE PBF_SOURCE_DIR="${CMAKE_CURRENT_SOURCE_DIR}")
endif()
