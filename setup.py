from glob import glob

from setuptools import find_packages, setup

PACKAGE = "polyforce_ros"

# Executables: `ros2 run polyforce_ros <name>` (colcon install) or `.venv/bin/<name>`.
CONSOLE_SCRIPTS = [
    "polyforce = polyforce_ros.cli:main",
    "driver_node = polyforce_ros.nodes.driver_node:main",
    "driver_lifecycle_node = polyforce_ros.nodes.driver_node:main_lifecycle",
    "compensation_node = polyforce_ros.nodes.compensation_node:main",
    "compensation_lifecycle_node = polyforce_ros.nodes.compensation_node:main_lifecycle",
    "calibration_node = polyforce_ros.nodes.calibration_node:main",
    "replay_node = polyforce_ros.nodes.replay_node:main",
    "recorder_node = polyforce_ros.nodes.recorder_node:main",
    "haptic_bridge_node = polyforce_ros.nodes.haptic_bridge_node:main",
]

setup(
    name=PACKAGE,
    version="0.1.0",
    packages=find_packages(exclude=["test", "test.*", "bench", "bench.*"]),
    data_files=[
        ("share/ament_index/resource_index/packages", [f"resource/{PACKAGE}"]),
        (f"share/{PACKAGE}", ["package.xml"]),
        (f"share/{PACKAGE}/config", sorted(glob("config/*.yaml") + glob("config/*.json") + glob("config/*.xml"))),
        (f"share/{PACKAGE}/launch", sorted(glob("launch/*.launch.py"))),
        (f"share/{PACKAGE}/urdf", sorted(glob("urdf/*.xacro"))),
        (f"share/{PACKAGE}/bags", sorted(glob("bags/*.mcap"))),
    ],
    install_requires=["setuptools"],
    zip_safe=True,
    maintainer="polyforce_ros developers",
    maintainer_email="dev@polyforce.invalid",
    description="Viscoelastic compensation of a polymer force sensor for haptic needle insertion",
    license="Apache-2.0",
    tests_require=["pytest"],
    entry_points={"console_scripts": CONSOLE_SCRIPTS},
)
