"""A Dask worker preload (test_worker_start.py): the first worker process that imports it, of all
those that see RAILBRAKE_TEST_DIE_ONCE (a marker file's path), dies there, while Dask starts it."""

import os

try:
    os.close(os.open(os.environ["RAILBRAKE_TEST_DIE_ONCE"], os.O_CREAT | os.O_EXCL | os.O_WRONLY))
except (KeyError, FileExistsError):
    pass
else:
    os._exit(1)
