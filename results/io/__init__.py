"""Files and pictures: atomic writers, result records, the sweep journal, field files (VTK/XDMF) and pictures."""
