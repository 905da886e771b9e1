# pbf_ros_node: the ROS layer (FluidDriver = FluidNode + the surface render thread, and
# their plain conversion functions); pbf_node and pbf_ros/FluidNodelet are thin shells over
# FluidDriver.
# The only code that knows ROS; it translates between the graph and pbf_core.
include_directories(${catkin_INCLUDE_DIRS})

add_library(pbf_ros_node
  src/ros/CameraInfoConversion.cpp
  src/ros/CloudConversion.cpp
  src/ros/DomainTransform.cpp
  src/ros/FluidDiagnostics.cpp
  src/ros/FluidDriver.cpp
  src/ros/FluidNode.cpp
  src/ros/FluidNodeDiagnostics.cpp
  src/ros/FluidNodeReconfigure.cpp
  src/ros/FluidNodeRobot.cpp
  src/ros/FluidNodeServices.cpp
  src/ros/FluidNodeSources.cpp
  src/ros/ObstacleMover.cpp
  src/ros/ParamsConversion.cpp
  src/ros/RealTimePacer.cpp
  src/ros/ReconfigureRecord.cpp
  src/ros/RenderCameraParams.cpp
  src/ros/RobotSource.cpp
  src/ros/SceneMarkers.cpp
  src/ros/SceneLoading.cpp
  src/ros/SimulationLoop.cpp
  src/ros/SimulationTasks.cpp
  src/ros/SnapshotBuffer.cpp
  src/ros/SolidWrenchPublishers.cpp
  src/ros/SolidWrenchTargets.cpp
  src/ros/StatsConversion.cpp
  src/ros/SurfaceImageConversion.cpp
  src/ros/SurfaceRenderThread.cpp
  src/ros/TfAttachments.cpp
  src/ros/TfStampGate.cpp
  src/ros/TopicRateDiagnostic.cpp)
target_include_directories(pbf_ros_node PUBLIC include ${CATKIN_DEVEL_PREFIX}/include)
# pbf_render brings its GL back-ends (OSMesa, EGL) but never libGL/libOpenGL.
target_link_libraries(pbf_ros_node PUBLIC pbf_core pbf_render pbf_robots ${catkin_LIBRARIES})
# The generated SimulationStats.h and FluidConfig.h must exist before we compile.
add_dependencies(pbf_ros_node ${PROJECT_NAME}_generate_messages_cpp ${PROJECT_NAME}_gencfg)

add_executable(pbf_node src/nodes/pbf_node.cpp)
target_link_libraries(pbf_node pbf_ros_node)

# The nodelet plugin (nodelet_plugins.xml, exported in package.xml). Its library name is
# the one the xml gives (lib/libpbf_fluid_nodelet).
add_library(pbf_fluid_nodelet src/nodelet/FluidNodelet.cpp)
target_link_libraries(pbf_fluid_nodelet pbf_ros_node)

install(TARGETS pbf_ros_node pbf_fluid_nodelet pbf_node
  ARCHIVE DESTINATION ${CATKIN_PACKAGE_LIB_DESTINATION}
  LIBRARY DESTINATION ${CATKIN_PACKAGE_LIB_DESTINATION}
  RUNTIME DESTINATION ${CATKIN_PACKAGE_BIN_DESTINATION})
