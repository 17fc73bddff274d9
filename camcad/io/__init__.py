"""Reading laws (DXF, tables) and writing DXF, CSV and JSON outputs."""
