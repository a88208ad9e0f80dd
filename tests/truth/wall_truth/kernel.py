"""The C transcription of engine.TwoBlockWall's step (csrc/wall_kernel.c), compiled on first use with the system's C
compiler (cc, -O2, no fast-math, no FMA contraction) into a per-source-hash cache directory and loaded with ctypes."""
import ctypes
import hashlib
import math
import os
import subprocess
import tempfile

import numpy as np

from .engine import TwoBlockWall

_SRC = os.path.join(os.path.dirname(os.path.abspath(__file__)), "csrc", "wall_kernel.c")
_lib = None


def _load():
    global _lib
    if _lib is not None:
        return _lib
    src = open(_SRC, "rb").read()
    tag = hashlib.sha1(src).hexdigest()[:12]
    root = os.environ.get("WALL_TRUTH_BUILD_DIR") or os.path.join(tempfile.gettempdir(), "wall_truth-%d" % os.getuid())
    os.makedirs(root, exist_ok=True)
    so = os.path.join(root, "wall_kernel-%s.so" % tag)
    if not os.path.exists(so):
        cc = os.environ.get("CC", "cc")
        tmp = so + ".%d.tmp" % os.getpid()
        subprocess.run([cc, "-O2", "-fPIC", "-shared", "-ffp-contract=off", "-fno-fast-math", "-o", tmp, _SRC, "-lm"],
                       check=True)
        os.replace(tmp, so)
    lib = ctypes.CDLL(so)
    dp = ctypes.POINTER(ctypes.c_double)
    lib.wt_state_size.restype = ctypes.c_int
    lib.wt_param_size.restype = ctypes.c_int
    lib.wt_init.argtypes = [dp, dp]
    lib.wt_step.argtypes = [dp, dp, ctypes.c_double, ctypes.c_double]
    lib.wt_steps.argtypes = [dp, dp, ctypes.c_double, ctypes.c_int, ctypes.c_double, ctypes.c_double]
    _lib = lib
    return lib


class FastWall(TwoBlockWall):
    """TwoBlockWall whose step runs in C. Same state, same algorithm; q and v are views of the C state."""

    def __init__(self, params):
        super().__init__(params)
        lib = _load()
        self._lib = lib
        itf = self.p["interface"]
        crushing = self.kind == "crushing"
        self._par = np.array([self.b, self.h1, self.h2, float(self.p["rho"]), self.g, self.Fp, self.mu,
                              self.mu_guide, self.beta, 1.0 if crushing else 0.0,
                              float(itf.get("n_fibres", 0)), float(itf.get("k_N_per_m3", 0.0)),
                              float(itf.get("c_Ns_per_m3", 0.0)), float(itf.get("fc_Pa", 0.0))])
        if crushing and not 2 <= int(itf["n_fibres"]) <= 41:
            raise ValueError("n_fibres must be in 2..41")
        self._st = np.zeros(lib.wt_state_size())
        self._pp = self._par.ctypes.data_as(ctypes.POINTER(ctypes.c_double))
        self._sp = self._st.ctypes.data_as(ctypes.POINTER(ctypes.c_double))
        lib.wt_init(self._pp, self._sp)

    # q, v live in the C state
    @property
    def q(self):
        return self._st[0:6]

    @q.setter
    def q(self, val):
        if hasattr(self, "_st"):
            self._st[0:6] = val

    @property
    def v(self):
        return self._st[6:12]

    @v.setter
    def v(self, val):
        if hasattr(self, "_st"):
            self._st[6:12] = val

    @property
    def driver(self):
        if not hasattr(self, "_st") or self._st[12] < 0.5:
            return None
        return float(self._st[13])

    @driver.setter
    def driver(self, val):
        if not hasattr(self, "_st"):
            return
        if val is None:
            self._st[12] = 0.0
        else:
            self._st[12], self._st[13] = 1.0, float(val)

    @property
    def last_driver_force(self):
        return float(self._st[14]) if hasattr(self, "_st") else 0.0

    @last_driver_force.setter
    def last_driver_force(self, val):
        pass

    @property
    def fallbacks(self):
        return int(self._st[15]) if hasattr(self, "_st") else 0

    @fallbacks.setter
    def fallbacks(self, val):
        pass

    def reset_status(self):
        n = self._lib.wt_state_size()
        nslot = (n - 16) - 2 * 41
        self._st[16:16 + nslot] = -1.0

    def step(self, h, ug):
        self._lib.wt_step(self._pp, self._sp, h, ug)

    def steps(self, h, n, ug0, ug1):
        self._lib.wt_steps(self._pp, self._sp, h, n, ug0, ug1)
