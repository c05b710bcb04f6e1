"""World layouts: geometry of a spec, rasters, generators and importers."""
