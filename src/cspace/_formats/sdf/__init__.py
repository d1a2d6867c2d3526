"""SDF (SDFormat): models, scopes and the pose graph as libsdformat resolves them."""
