// anchordb_ros: `rosrun`-style entry point (see bridge_node.h and README.md).
#include "clients/ros/bridge_node.h"

#include <cstdio>

int main(int argc, char** argv) {
  ros::init(argc, argv, "anchordb_ros");
  ros::NodeHandle nh, pnh("~");
  const anchordb::ros_bridge::NodeParams params = anchordb::ros_bridge::LoadParams(pnh);
  try {
    anchordb::ros_bridge::BridgeNode node(nh, pnh, params);
    ros::spin();
    std::printf("%s\n", node.Finish().c_str());
    std::fflush(stdout);
  } catch (const std::exception& e) {  // bad settings (the observation rule's), not a server that is down
    ROS_FATAL("anchordb_ros: %s", e.what());
    return 2;
  }
  return 0;
}
