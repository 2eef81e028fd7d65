"""Tools built on the environment and the level files: the CEM solver of level solutions and the engine demo."""
