// The node's start-up settings that are checked after they are read (NodeParams.h): a value
// out of its range, or a frame id tf cannot use, falls back to the default with a warning
// that names the parameter (a helper probe: each was taken in silence).
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "pbf_ros/ros/NodeParams.h"

namespace {

TEST(NodeParams, ANumberOutOfItsRangeFallsBackWithAWarningNamingIt) {
  std::string warning;
  EXPECT_EQ(pbf_ros::withinRange("max_lag", 0.5, 1e-3, 3600.0, 0.1, warning), 0.5);
  EXPECT_EQ(warning, "");
  EXPECT_EQ(pbf_ros::withinRange("max_lag", -1.0, 1e-3, 3600.0, 0.1, warning), 0.1);
  EXPECT_EQ(warning, "~max_lag -1 is not in [0.001, 3600]; using 0.1");
  EXPECT_EQ(pbf_ros::withinRange("diagnostics/rtf_warn_ratio", NAN, 0.0, 1.0, 0.9, warning), 0.9);
  EXPECT_NE(warning.find("~diagnostics/rtf_warn_ratio nan is not in [0, 1]"), std::string::npos) << warning;
  EXPECT_EQ(pbf_ros::withinRange("render_nice", 100, 0, 19, 10, warning), 10);
  EXPECT_NE(warning.find("~render_nice 100"), std::string::npos) << warning;
  EXPECT_EQ(pbf_ros::withinRange("render_nice", 19, 0, 19, 10, warning), 19);  // the ends are in
  EXPECT_EQ(warning, "");
}

TEST(NodeParams, AFrameIdTfCannotUseFallsBackWithAWarningNamingIt) {
  std::string warning;
  EXPECT_EQ(pbf_ros::usableFrameId("world_frame", "map", "world", warning), "map");
  EXPECT_EQ(warning, "");
  EXPECT_EQ(pbf_ros::usableFrameId("world_frame", "", "world", warning), "world");
  EXPECT_EQ(warning, "~world_frame '' is not a frame id tf can use (empty); using 'world'");
  EXPECT_EQ(pbf_ros::usableFrameId("camera_frame_id", "/cam", "fluid_camera_optical", warning),
            "fluid_camera_optical");
  EXPECT_NE(warning.find("leading '/'"), std::string::npos) << warning;
}

TEST(NodeParams, AValueOfTheWrongTypeIsDescribedAsTheUserWroteIt) {
  EXPECT_EQ(pbf_ros::describeParam(XmlRpc::XmlRpcValue(1)), "1 (an integer)");
  EXPECT_EQ(pbf_ros::describeParam(XmlRpc::XmlRpcValue(std::string("maybe"))), "'maybe' (a string)");
  EXPECT_EQ(pbf_ros::describeParam(XmlRpc::XmlRpcValue(true)), "true (a boolean)");
}

}  // namespace
