"""test_model.py — the Python module (python/albatros.py) over the shared
library: every golden vector replayed with its frames' numbers, cycle counts
and CRCs checked against expected.frames; the GP's stream of the built-in
scene equal to the vector's; a cocotb-style lockstep loop as the FIFO's
producer; events and errors.  Run by tests/python.sh; ends with
"N passed, N failed"."""

import os
import sys
import traceback

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "..", "python"))
import albatros  # noqa: E402

passed = failed = 0


def check(cond, what):
    global passed, failed
    if cond:
        passed += 1
    else:
        failed += 1
        print("FAIL:", what)


def vector_profile(d):
    """--profile and --set of a vector's options file."""
    profile, sets = "a512", []
    try:
        toks = open(os.path.join(d, "options")).read().split()
    except OSError:
        toks = []
    for i, t in enumerate(toks):
        if t == "--profile":
            profile = toks[i + 1]
        elif t == "--set":
            sets.append(toks[i + 1])
    return profile, sets


def test_vectors():
    root = "test-vectors"
    n = 0
    for name in sorted(os.listdir(root)):
        d = os.path.join(root, name)
        frames = os.path.join(d, "expected.frames")
        if not os.path.exists(frames):
            continue
        expected = [tuple(l.split()) for l in open(frames) if l.strip()]
        profile, sets = vector_profile(d)
        words = albatros.read_stream(os.path.join(d, "expected.stream"))
        got = []
        with albatros.Model(profile, sets, events=albatros.EV_FRAME) as m:
            check(m.push(words) == len(words), "%s: all words taken" % name)
            while not m.done:
                m.run(until=albatros.EV_FRAME)
                got += [(str(e.number), str(e.cycles), "%08x" % e.crc) for e in m.events()]
        check(got == expected, "%s: frames %s, expected %s" % (name, got[:2], expected[:2]))
        n += 1
    check(n >= 12, "%d vectors" % n)


def test_compile_builtin():
    words = albatros.compile_scene(None, "a512")
    check(words == albatros.read_stream("test-vectors/builtin/expected.stream"),
          "the built-in scene's stream is the builtin vector's")
    try:
        albatros.compile_scene("/nonexistent.scene", "a512")
        check(False, "a missing scene raises")
    except albatros.AlbatrosError as e:
        check("/nonexistent.scene" in str(e), "the error names the file: %s" % e)


def test_lockstep_producer():
    # a testbench pushing a word whenever the FIFO takes one, cycle by cycle
    sets = ["fifo_depth=2", "gp_face_cycles=0", "gp_edge_cycles=0", "gp_frame_cycles=0"]
    words = albatros.compile_scene(None, "t32", sets)
    ref = albatros.Model("t32", sets, events=albatros.EV_ALL)
    ref.push(words)
    ref_events = []
    while not ref.done:
        ref.step(5000)
        ref_events += ref.events()
    m = albatros.Model("t32", sets, producer="external", events=albatros.EV_ALL)
    i = refused = 0
    got = []
    while not m.done and m.cycle < 10 ** 7:
        if i < len(words):
            k = m.push(words[i:i + 8])
            check(k <= 1, "one word a cycle") if k > 1 else None
            i += k
            refused += k == 0
        m.step(1)
        got += m.events()
    check(i == len(words) and refused > 0, "all words pushed, %d refusals" % refused)
    key = lambda e: bytes(e)
    check([key(e) for e in got] == [key(e) for e in ref_events],
          "external producer: %d events, GP stage: %d" % (len(got), len(ref_events)))
    writes = [e for e in got if e.kind == albatros.EV_WRITE]
    check(writes and all(e.x < 32 and e.y < 32 for e in writes), "writes on the 32x32 screen")
    check(got[-1].kind in (albatros.EV_POP, albatros.EV_FRAME), "the last event: %r" % got[-1])


def test_errors():
    try:
        albatros.Model("no-such-profile")
        check(False, "an unknown profile raises")
    except albatros.AlbatrosError as e:
        check("no-such-profile" in str(e), str(e))
    m = albatros.Model("t32")
    words = albatros.compile_scene(None, "t32")
    try:
        m.push(words + [0xFF000000])
        m.run()
        check(False, "a word after END raises")
    except albatros.AlbatrosError as e:
        check("after END" in str(e), str(e))
    check(albatros.version() == "0.1.0", albatros.version())


for name, fn in list(globals().items()):
    if name.startswith("test_") and callable(fn):
        try:
            fn()
        except Exception:
            failed += 1
            print("FAIL: %s raised:" % name)
            traceback.print_exc()
print("%d passed, %d failed" % (passed, failed))
sys.exit(1 if failed or not passed else 0)
