"""`melfa ros`: the robot as a ROS 1 node (being built)."""
