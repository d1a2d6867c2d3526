"""MJCF: the pre-scan of every file MuJoCo reads, MuJoCo's compiler in a child, keyframes."""
