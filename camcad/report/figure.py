"""Plots (PNG, matplotlib's Agg backend), one module per analysis. Import matplotlib lazily."""


def pyplot():
    """matplotlib.pyplot with the headless Agg backend selected."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt
