"""ROS 2 nodes: the plant (sim, rig and replay backends), the controller, the recorder.

The only part of the package that imports rclpy and message packages.
Submodules import them; importing this package alone does not, so the
command line can explain a missing ROS with one line (:func:`require_rclpy`).
"""
from ..errors import ConfigError


def require_rclpy() -> None:
    """ConfigError with the fix if rclpy or the message packages are not importable."""
    try:
        import diagnostic_msgs.msg  # noqa: F401
        import rclpy  # noqa: F401
        import sensor_msgs.msg  # noqa: F401
        import trajectory_msgs.msg  # noqa: F401
    except ImportError as exc:
        raise ConfigError(f'ROS 2 Python is not available ({exc.name} missing): source a ROS 2 '
                          "Jazzy install or `pip install -e '.[ros]'`") from None
