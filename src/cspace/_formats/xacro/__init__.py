"""xacro: URDF expanded in a confined child process, then read as URDF."""
