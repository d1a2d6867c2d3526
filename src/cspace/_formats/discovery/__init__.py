"""A folder's search: robot descriptions told from other files without parsing them."""
