"""The accuracy/time sweep behind model/tools/sweep.py (`hrpp sweep`), by concern:

    tasks    the parameters, the grid, presets, each configuration's hrpp options, the rows of a
             run's report, the CSV
    pareto   Pareto fronts and the groups they compare
    labels   configurations and figures in words
    plots    the PNG plots (--plots)
    report   the Markdown report (--report)
    doc      the generated blocks of docs/results.md (--doc)

Its modules import pyhrpp: the repository's root must be on sys.path (sweep.py puts it there).
"""
