"""The palette shared by the host renderer (`kinetix_cli.viz.render`) and the pixel observation
(`kinetix_cli.env.pixels`), so a picture and what the agent sees never disagree. RGB, 0..255."""

Colour = tuple[int, int, int]

BACKGROUND: Colour = (255, 255, 255)
ROLE_COLOURS: tuple[Colour, ...] = ((160, 160, 160), (0, 204, 0), (0, 102, 204), (255, 102, 102))
"""Fill per role: 0 neutral, 1 green, 2 blue, 3 red."""
FIXED_NEUTRAL: Colour = (80, 80, 80)
"""Fill of a fixed neutral shape (and of a neutral floor)."""
FIXED_ROLE_SCALE = 0.5
"""A fixed shape with a role is filled with its role colour times this."""
MOTOR_COLOURS: tuple[Colour, ...] = ((150, 80, 210), (0, 175, 200), (150, 150, 0), (160, 95, 45))
"""Motor marker per binding 0..3."""
AUTO_MOTOR_COLOUR: Colour = (230, 0, 150)
PLAIN_JOINT_COLOUR: Colour = (0, 0, 0)
"""Marker of a joint without a motor in the pixel observation."""
THRUSTER_COLOURS: tuple[Colour, ...] = ((255, 120, 0), (235, 195, 0))
"""Thruster marker per binding 0..1."""
