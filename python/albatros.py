"""albatros — the golden model of the Albatros half-plane video processor,
from Python: ctypes over libalbatros (the standard library only), what a
cocotb testbench imports.  docs/cosim.md says what each event means.

    import albatros
    m = albatros.Model("t32", sets=["edge_units=3"], events=albatros.EV_ALL)
    m.push(albatros.compile_scene(None, "t32"))
    while not m.done:
        m.run(until=albatros.EV_FRAME)
        for ev in m.events():
            if ev.kind == albatros.EV_FRAME:
                print(ev.number, ev.cycle, ev.cycles, hex(ev.crc))

The library is found as $ALBATROS_LIB if set, else libalbatros.so.0 on the
loader's path (installed: make install).
"""

import ctypes
import os

__all__ = ["Model", "Event", "AlbatrosError", "compile_scene", "read_stream", "version",
           "EV_PUSH", "EV_POP", "EV_LOAD", "EV_START", "EV_CELL", "EV_END", "EV_FILL",
           "EV_WRITE", "EV_FRAME", "EV_ALL", "KIND_NAMES"]

# event kinds, one bit each (albatros/sim.h, ALB_EV_*)
EV_PUSH, EV_POP, EV_LOAD, EV_START, EV_CELL = 1 << 0, 1 << 1, 1 << 2, 1 << 3, 1 << 4
EV_END, EV_FILL, EV_WRITE, EV_FRAME = 1 << 5, 1 << 6, 1 << 7, 1 << 8
EV_ALL = 0x1FF
KIND_NAMES = {EV_PUSH: "push", EV_POP: "pop", EV_LOAD: "load", EV_START: "start",
              EV_CELL: "cell", EV_END: "end", EV_FILL: "fill", EV_WRITE: "write",
              EV_FRAME: "frame"}

_FIDELITY = {"functional": 0, "timed": 1, "cycle": 2}
_PRODUCER = {"gp": 0, "external": 1, "tb": 1}
_STOP = {0: "cycles", 1: "event", 2: "done"}


class AlbatrosError(Exception):
    """An error of the model, with the library's located message."""


class Event(ctypes.Structure):
    """One event (alb_event); the fields a kind does not use are 0."""
    _fields_ = [
        ("cycle", ctypes.c_uint64), ("kind", ctypes.c_uint32), ("face", ctypes.c_uint32),
        ("index", ctypes.c_uint64), ("word", ctypes.c_uint32), ("slot", ctypes.c_uint32),
        ("edges", ctypes.c_uint32), ("x", ctypes.c_uint32), ("y", ctypes.c_uint32),
        ("wl", ctypes.c_uint8), ("hl", ctypes.c_uint8), ("level", ctypes.c_uint8),
        ("result", ctypes.c_uint8), ("depth", ctypes.c_uint32),
        ("rgb", ctypes.c_uint16 * 3), ("number", ctypes.c_uint32),
        ("cycles", ctypes.c_uint64), ("crc", ctypes.c_uint32),
    ]

    @property
    def name(self):
        return KIND_NAMES.get(self.kind, "unknown")

    def __repr__(self):
        return "<%s at cycle %d>" % (self.name, self.cycle)


class _Diag(ctypes.Structure):
    _fields_ = [("file", ctypes.c_char * 256), ("line", ctypes.c_uint), ("col", ctypes.c_uint),
                ("offset", ctypes.c_longlong), ("msg", ctypes.c_char * 512),
                ("warn", ctypes.c_void_p), ("warnings", ctypes.c_uint)]

    def text(self):
        buf = ctypes.create_string_buffer(1024)
        _lib.alb_diag_format(ctypes.byref(self), buf, len(buf))
        return buf.value.decode("utf-8", "replace")


class _Config(ctypes.Structure):
    _fields_ = [("fidelity", ctypes.c_int), ("producer", ctypes.c_int),
                ("events", ctypes.c_uint32), ("threads", ctypes.c_uint),
                ("name", ctypes.c_char_p)]


def _load():
    path = os.environ.get("ALBATROS_LIB") or "libalbatros.so.0"
    lib = ctypes.CDLL(path)
    sig = {
        "alb_version": (ctypes.c_char_p, []),
        "alb_event_size": (ctypes.c_size_t, []),
        "alb_free": (None, [ctypes.c_void_p]),
        "alb_diag_format": (ctypes.c_int, [ctypes.c_void_p, ctypes.c_char_p, ctypes.c_size_t]),
        "alb_model_config_default": (None, [ctypes.c_void_p]),
        "alb_model_open": (ctypes.c_int, [ctypes.POINTER(ctypes.c_void_p), ctypes.c_char_p,
                                          ctypes.POINTER(ctypes.c_char_p), ctypes.c_void_p,
                                          ctypes.c_void_p]),
        "alb_model_destroy": (None, [ctypes.c_void_p]),
        "alb_model_push": (ctypes.c_size_t, [ctypes.c_void_p, ctypes.POINTER(ctypes.c_uint32),
                                             ctypes.c_size_t]),
        "alb_model_step": (ctypes.c_int, [ctypes.c_void_p, ctypes.c_uint64]),
        "alb_model_run": (ctypes.c_int, [ctypes.c_void_p, ctypes.c_uint32, ctypes.c_uint64,
                                         ctypes.POINTER(ctypes.c_int)]),
        "alb_model_events": (ctypes.c_size_t, [ctypes.c_void_p,
                                               ctypes.POINTER(ctypes.POINTER(Event))]),
        "alb_model_consume": (None, [ctypes.c_void_p, ctypes.c_size_t]),
        "alb_model_cycle": (ctypes.c_uint64, [ctypes.c_void_p]),
        "alb_model_done": (ctypes.c_bool, [ctypes.c_void_p]),
        "alb_model_frames": (ctypes.c_uint, [ctypes.c_void_p]),
        "alb_model_fifo_level": (ctypes.c_uint64, [ctypes.c_void_p]),
        "alb_model_error": (ctypes.c_char_p, [ctypes.c_void_p]),
        "alb_ws_read_file": (ctypes.c_int, [ctypes.c_char_p,
                                            ctypes.POINTER(ctypes.POINTER(ctypes.c_uint32)),
                                            ctypes.POINTER(ctypes.c_size_t), ctypes.c_void_p]),
        "alb_gp_compile_file": (ctypes.c_int, [ctypes.c_char_p, ctypes.c_char_p,
                                               ctypes.POINTER(ctypes.c_char_p),
                                               ctypes.POINTER(ctypes.POINTER(ctypes.c_uint32)),
                                               ctypes.POINTER(ctypes.c_size_t), ctypes.c_void_p]),
    }
    for name, (res, args) in sig.items():
        fn = getattr(lib, name)
        fn.restype = res
        fn.argtypes = args
    if lib.alb_event_size() != ctypes.sizeof(Event):
        raise AlbatrosError("libalbatros's alb_event is %d bytes, this module's %d: a "
                            "different version" % (lib.alb_event_size(), ctypes.sizeof(Event)))
    return lib


_lib = _load()


def version():
    """The library's version ("0.1.0")."""
    return _lib.alb_version().decode()


def _strings(items):
    items = ["%s=%s" % kv for kv in items.items()] if isinstance(items, dict) else list(items or [])
    arr = (ctypes.c_char_p * (len(items) + 1))()
    for i, s in enumerate(items):
        arr[i] = s.encode()
    arr[len(items)] = None
    return arr


def _take_words(call):
    w = ctypes.POINTER(ctypes.c_uint32)()
    n = ctypes.c_size_t()
    d = _Diag()
    if call(ctypes.byref(w), ctypes.byref(n), ctypes.byref(d)):
        raise AlbatrosError(d.text())
    try:
        return list(w[:n.value])
    finally:
        _lib.alb_free(w)


def read_stream(path):
    """The words of a stream file (binary or $readmemh text) as a list."""
    return _take_words(lambda w, n, d: _lib.alb_ws_read_file(path.encode(), w, n, d))


def compile_scene(scene, profile="a512", sets=None):
    """The GP's word stream of a scene file (None: the built-in scene)."""
    arr = _strings(sets)
    path = scene.encode() if scene is not None else None
    return _take_words(lambda w, n, d: _lib.alb_gp_compile_file(path, profile.encode(), arr,
                                                                w, n, d))


class Model:
    """The golden model (alb_model): push words, step, read events."""

    def __init__(self, profile="a512", sets=None, fidelity="cycle", producer="gp",
                 events=EV_FRAME, name="<python>"):
        cfg = _Config()
        _lib.alb_model_config_default(ctypes.byref(cfg))
        cfg.fidelity = _FIDELITY[fidelity]
        cfg.producer = _PRODUCER[producer]
        cfg.events = events
        self._name = name.encode()
        cfg.name = self._name
        self._m = ctypes.c_void_p()
        d = _Diag()
        if _lib.alb_model_open(ctypes.byref(self._m), profile.encode(), _strings(sets),
                               ctypes.byref(cfg), ctypes.byref(d)):
            raise AlbatrosError(d.text())

    def close(self):
        if self._m:
            _lib.alb_model_destroy(self._m)
            self._m = ctypes.c_void_p()

    def __del__(self):
        self.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def _check(self, rc):
        if rc:
            raise AlbatrosError(self.error)

    @property
    def error(self):
        return _lib.alb_model_error(self._m).decode("utf-8", "replace")

    def push(self, words):
        """Offer words in order; how many were taken (an external producer:
        at most one, none while the FIFO is full)."""
        words = list(words)
        arr = (ctypes.c_uint32 * len(words))(*words)
        k = _lib.alb_model_push(self._m, arr, len(words))
        if k < len(words) and self.error:
            raise AlbatrosError(self.error)
        return k

    def step(self, cycles=1):
        self._check(_lib.alb_model_step(self._m, cycles))

    def run(self, until=0, max_cycles=1 << 62):
        """Run to a cycle with an event of a kind in `until`, at most
        max_cycles, or the end: "event", "cycles" or "done"."""
        why = ctypes.c_int()
        self._check(_lib.alb_model_run(self._m, until, max_cycles, ctypes.byref(why)))
        return _STOP[why.value]

    def events(self):
        """The recorded events not read yet, oldest first (copies)."""
        p = ctypes.POINTER(Event)()
        n = _lib.alb_model_events(self._m, ctypes.byref(p))
        out = [Event.from_buffer_copy(p[i]) for i in range(n)]
        _lib.alb_model_consume(self._m, n)
        return out

    @property
    def cycle(self):
        return _lib.alb_model_cycle(self._m)

    @property
    def done(self):
        return bool(_lib.alb_model_done(self._m))

    @property
    def frames(self):
        return _lib.alb_model_frames(self._m)

    @property
    def fifo_level(self):
        return _lib.alb_model_fifo_level(self._m)
