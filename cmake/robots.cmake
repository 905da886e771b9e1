# pbf_robots: robots (URDF) as fluid solids. Reads a URDF and its meshes through the ROS
# libraries that already do it (urdf, geometric_shapes + assimp) and hands pbf_core plain
# Obstacles; needs no ROS master. The node links it to attach a robot's links to tf.
find_package(urdf REQUIRED)
find_package(geometric_shapes REQUIRED)
find_package(roslib REQUIRED)  # package:// paths, to check a mesh file before it is read
# Boost.Regex for ~robot_link_regex: it bounds a match's work, std::regex does not (UrdfSolids.cpp).
find_package(Boost REQUIRED COMPONENTS regex)

add_library(pbf_robots
  src/ros/MeshResource.cpp
  src/ros/UrdfSolids.cpp)
target_include_directories(pbf_robots PUBLIC include ${urdf_INCLUDE_DIRS} ${geometric_shapes_INCLUDE_DIRS}
  ${roslib_INCLUDE_DIRS})
target_link_libraries(pbf_robots PUBLIC pbf_core ${urdf_LIBRARIES} ${geometric_shapes_LIBRARIES}
  ${roslib_LIBRARIES}
  PRIVATE Boost::regex)

install(TARGETS pbf_robots
  ARCHIVE DESTINATION ${CATKIN_PACKAGE_LIB_DESTINATION}
  LIBRARY DESTINATION ${CATKIN_PACKAGE_LIB_DESTINATION})
install(DIRECTORY urdf DESTINATION ${CATKIN_PACKAGE_SHARE_DESTINATION})
