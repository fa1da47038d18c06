"""Where the package's config files are: a source checkout, a pip install or a ROS install."""
from __future__ import annotations

import os
from pathlib import Path

from ..errors import ConfigError

PACKAGE = 'pneumatic_servo'


def config_dirs() -> list[Path]:
    """Candidate ``config/`` directories, most specific first."""
    dirs = []
    env = os.environ.get('PNEUMATIC_SERVO_CONFIG_DIR')
    if env:
        dirs.append(Path(env))
    dirs.append(Path(__file__).resolve().parents[2] / 'config')  # source checkout, pip -e
    try:  # a ROS install (colcon): share/pneumatic_servo/config
        from ament_index_python.packages import get_package_share_directory
        dirs.append(Path(get_package_share_directory(PACKAGE)) / 'config')
    except Exception:  # not installed through ament: fine
        pass
    return dirs


def find_config(name: str) -> Path:
    """Path of the shipped config file ``name`` (e.g. 'rig_pci6229.yaml')."""
    for d in config_dirs():
        if (d / name).is_file():
            return d / name
    raise ConfigError(f'cannot find {name} in {", ".join(str(d) for d in config_dirs())}; '
                      'set PNEUMATIC_SERVO_CONFIG_DIR or give the path')


def resolve(path: str, default_name: str = '') -> Path | None:
    """``path`` if given (must exist), else the shipped ``default_name``, else None."""
    if path:
        p = Path(path).expanduser()
        if not p.is_file():
            raise ConfigError(f'config file {p} does not exist')
        return p
    return find_config(default_name) if default_name else None
