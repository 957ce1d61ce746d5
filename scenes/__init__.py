"""Scene builders and the catalog of block assemblies (JSON files in scenes/catalog/)."""
