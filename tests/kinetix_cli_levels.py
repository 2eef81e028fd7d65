"""Small level descriptions shared by the CLI and level-file tests."""

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
