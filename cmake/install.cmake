# The install space (catkin_make_isolated --install, or cmake --install of this build):
# everything `roslaunch pbf_ros fluid.launch` needs with no source or build tree around.
# The targets install themselves (core.cmake, render.cmake, robots.cmake, ros.cmake); the
# node finds shaders, scenes and meshes through ros::package::getPath, i.e. in
# share/pbf_ros, so they go there with the same layout as in the source tree.
install(TARGETS pbf_core
  ARCHIVE DESTINATION ${CATKIN_PACKAGE_LIB_DESTINATION}
  LIBRARY DESTINATION ${CATKIN_PACKAGE_LIB_DESTINATION})
install(DIRECTORY include/pbf_ros/ DESTINATION ${CATKIN_PACKAGE_INCLUDE_DESTINATION})
install(DIRECTORY launch config DESTINATION ${CATKIN_PACKAGE_SHARE_DESTINATION})
install(FILES nodelet_plugins.xml DESTINATION ${CATKIN_PACKAGE_SHARE_DESTINATION})
# Python nodes that launch files start (the benchmark plotting and mesh generation are
# developer tools of the source tree, not installed).
catkin_install_python(PROGRAMS
  scripts/move_frame.py
  scripts/pouring_arm_trajectory.py
  scripts/static_frames.py
  scripts/measure_rtf.py
  scripts/rviz_for_node.py
  DESTINATION ${CATKIN_PACKAGE_BIN_DESTINATION})
