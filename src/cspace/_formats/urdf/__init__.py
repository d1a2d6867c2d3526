"""URDF: the reader, urdfdom's numbers, Drake's joints and the document Pinocchio parses."""
