from pathlib import Path


REPO = Path(__file__).resolve().parents[1]


def pytest_report_header(config):
    from railbrake import _core
    return f"railbrake C core: {_core.lib._name}"


def pytest_collection_modifyitems(config, items):
    """The files that hold a slow test first, the others after, each in collection order. With
    `-n N --dist loadfile --no-loadscope-reorder` (make test) xdist hands files out in this order,
    so a long file (the paced HIL stop, the documentation's command blocks) starts at the beginning
    and the short ones fill the workers around it, instead of a long one starting last and running
    alone at the end (xdist's default order is by number of tests, which puts them last)."""
    slow_files = {item.path for item in items if item.get_closest_marker("slow")}
    items.sort(key=lambda item: item.path not in slow_files)   # stable: collection order within each
