"""Small level descriptions shared by the tests."""

CAR = {
    "format": "kinetix-level/1",
    "name": "car",
    "size": "s",
    "bodies": [
        {"name": "chassis", "shape": "box", "size": [0.8, 0.2], "position": [1.0, 0.8], "role": "green"},
        {"name": "wheel", "shape": "circle", "radius": 0.2, "position": [1.0, 0.6]},
        {"name": "goal", "shape": "circle", "radius": 0.3, "position": [4.5, 0.7], "role": "blue", "fixed": True},
    ],
    "joints": [{"a": "chassis", "b": "wheel", "anchor": [1.0, 0.6], "motor": {"binding": 2, "speed": 0.5}}],
    "thrusters": [{"body": "chassis", "direction_deg": 90, "power": 2.0, "binding": 1}],
}

FALL = {
    "format": "kinetix-level/1",
    "name": "fall",
    "description": "A green ball drops 2 m onto a fixed blue ball: solved by gravity alone, whatever the agent does.",
    "size": "s",
    "bodies": [
        {"name": "green", "shape": "circle", "radius": 0.2, "position": [2.5, 3.0], "role": "green"},
        {"name": "blue", "shape": "circle", "radius": 0.2, "position": [2.5, 0.6], "role": "blue", "fixed": True},
    ],
}
"""A level whose episode length measures only simulated time: ~25 steps at frame skip 2 and dt 1/60 s."""

PUSH = {
    "format": "kinetix-level/1",
    "size": "s",
    "bodies": [
        {"name": "g", "shape": "box", "size": [0.3, 0.3], "position": [1.0, 0.55], "role": "green", "friction": 0},
        {"name": "b", "shape": "circle", "radius": 0.15, "position": [3.0, 0.55], "role": "blue", "fixed": True},
    ],
    "thrusters": [{"body": "g", "direction_deg": 0, "power": 0.5, "binding": 1}],
}
"""A frictionless green box pushed by thruster binding 1 towards a blue ball 2 m to the right."""
