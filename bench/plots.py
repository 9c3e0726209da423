"""Plots of the benchmark reports, written as PNGs with matplotlib (which the GPU machine
lacks: `pyplot()` is None there, and the reports go without plots)."""
import importlib.util


def pyplot():
    """matplotlib.pyplot drawing off-screen, or None where matplotlib is missing."""
    if importlib.util.find_spec("matplotlib") is None:
        return None
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt


def save(plt, figure, axes, labels, title, path, legend_size=8):
    """Label the axes, title and legend the plot, and write it as a PNG."""
    axes.set_xlabel(labels[0])
    axes.set_ylabel(labels[1])
    axes.set_title(title, fontsize=9)
    axes.legend(fontsize=legend_size)
    figure.tight_layout()
    figure.savefig(path)
    plt.close(figure)
    return path
