# pbf_ros_node and pbf_node: see issue 3
