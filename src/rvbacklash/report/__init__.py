"""Outputs: rich tables for the terminal, SVG figures, the HTML report, JSON/CSV files. The
report layer renders results it is given; it never loads a design or runs a model."""
