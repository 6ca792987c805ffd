"""What a case records: the output table as index arrays, the results read back, the spectra."""
