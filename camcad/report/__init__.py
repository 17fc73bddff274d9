"""The report layer: plots (functions that return matplotlib Figures) and the output files of each command.

The only place, on the analyses' side, where matplotlib and the file writers are used.
"""
