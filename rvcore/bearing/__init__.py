"""A bearing as data: its geometry and materials, its imperfections, its contact and friction laws as records, and the flat arrays the kernels read."""
