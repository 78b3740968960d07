"""ROS-free physics of polyforce_ros: numpy/scipy only (no rclpy import anywhere here).

- :mod:`.expconv`        exact, stable exponential convolution (the shared recursion)
- :mod:`.viscoelastic`   Maxwell, Kelvin-Voigt, Zener, Burgers: J(t), G(t), simulate, compensate
- :mod:`.identification` creep-segment detection, creep fitting, model selection
- :mod:`.chain`          the sensor as a chain of elements (forward / backward / streaming)
- :mod:`.metrics`        error metrics
"""
