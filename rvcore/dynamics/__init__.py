"""The equations of motion: raceways, the ball contacts of a row, the right-hand side, its stiff tangent, the energies."""
