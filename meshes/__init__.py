"""gmsh builders for the r-z section of a shaft-bearing-housing stack; meshes cached by hash."""
