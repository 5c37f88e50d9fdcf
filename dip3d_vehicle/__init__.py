"""dip3d-vehicle: DIP-3D diver pointing as an ArduSub MAVLink behaviour controller.

OpenBLAS (numpy's and scipy's matrix products: descriptor matching, selection) is limited to one
thread unless ``OPENBLAS_NUM_THREADS`` is set: perception runs its own threads (the two eyes, SIFT
and the corridor concurrently), and OpenBLAS's spinning worker threads on top of them cost 15 ms of
CPU per matching of ~500 x 500 corridor features on 2 cores for 2.6 ms of work (issue 16). It takes
effect when this package is imported before numpy (the ``dip3d-vehicle`` command, ``python -m sitl...``).
"""

import os as _os

_os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

__version__ = "0.1.0"
