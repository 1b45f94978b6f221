"""Outputs: rich tables for the terminal, JSON and CSV files."""
