"""The model beside the running rig: live k-step predictions, each window judged against its
own prediction floor, a CUSUM per channel with a stated false-alarm rate per hour, the
regime where a departure concentrates, and the tracked effects fitted when one departs.
Pure (no rclpy): the ROS node (:mod:`pneumatic_servo.ros.monitor_node`) feeds it.

* :mod:`.judge`: each window against its own floor (a parametric bootstrap of the window);
* :mod:`.cusum`: windows' p-values -> a verdict per channel at a stated rate per hour;
* :mod:`.core`: :class:`~.core.Monitor`, the sliding buffer, baseline, decimation, reports;
* :mod:`.tracking`: the tracked effects' fits and their alerts (the fleet's change test);
* :mod:`.assemble`: samples from the interface topics' messages (commands paired by the
  publishers' source timestamps);
* :mod:`.floorfile`: the floor file a baseline saves and a later run loads;
* :mod:`.worker`: the judge and the fits in processes of their own.

Submodules are imported where used: the worker processes start from here without the
model's compiled kernels.
"""
