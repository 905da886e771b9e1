# Unit tests (GoogleTest, no ROS master) and rostest tests, all run by ctest.
# Each layer keeps its own list in test/<layer>.cmake.
include(test/core_tests.cmake)
include(test/render_tests.cmake OPTIONAL)
include(test/ros_tests.cmake OPTIONAL)
include(test/tools_tests.cmake OPTIONAL)
