"""Collision checking: the 1985 coarse + fine check, the python-fcl exact check, the LED sensor.

The simulator calls ``CollisionWorld.check`` (or ``check_scene``) at every motion step and
``led_hits`` on CLOSE/CLOSEI/GRASP. python-fcl is imported only when the exact checker is used.

Import from the modules themselves: ``world`` (CollisionWorld, Finding, ThesisChecker,
check_scene, default_skip), ``thesis`` (check_pair, margin, segment_hits_polyhedron), ``grasp``
(led_hits), ``frames``, ``exact``. The package loads none of them: the first picture asks the
LED sensor (``grasp``), and the checks themselves load with the first check (issue 25, the start).
"""
