"""Standard normals drawn inside compiled kernels: xoshiro256++ bits, ziggurat normals.

Why: drawing through numba's ``Generator`` costs an indirect call per number (~3.6 ns a
normal, ~96 % of the linear engine's time). A generator whose state lives in the kernel's
registers costs ~1 ns a number.

- Bits: xoshiro256++ (Blackman & Vigna, "Scrambled linear pseudorandom number generators",
  ACM TOMS 47 (2021); 256-bit state, period 2^256 - 1, passes BigCrush; Julia's default
  generator). Block b of a run starts from the state
  ``SeedSequence(seed, spawn_key=(*stream, b)).generate_state(4, uint64)``: the numbers of a
  block depend on (seed, stream, block) only, never on threads or scheduling.
- Normals: the ziggurat of Marsaglia & Tsang (J. Stat. Softw. 5(8), 2000) with 256 layers,
  r = 3.6541528853610088, layer area v = 4.92867323399e-3, in the 52-bit form numpy uses:
  one 64-bit word gives the layer (8 low bits), the sign (1 bit) and a 52-bit abscissa; ~98.8 %
  of draws are accepted at once, the rest go to the wedge test or Marsaglia's tail algorithm.
- The layer edges are stored below as literals (``repr`` round-trips exactly), not computed at
  import: a last-digit difference of a platform's ``exp``/``log`` would otherwise change the
  numbers. ``layer_edges()`` recomputes them (a test compares).
"""

from __future__ import annotations

import math

import numpy as np
from numpy.random import SeedSequence

from rvbacklash._numba import njit

ZIGGURAT_R = 3.6541528853610088  # start of the tail (Marsaglia & Tsang 2000, 256 layers)
ZIGGURAT_V = 4.92867323399e-3  # area of every layer (unnormalised density exp(-x^2/2))

# x_0 = v / f(r) (the base layer's equivalent width), x_1 = r, x_{i+1} = f^-1(f(x_i) + v / x_i),
# x_256 = 0, with f(x) = exp(-x^2 / 2): the output of layer_edges() on x86-64 glibc.
LAYER_EDGES = (
    3.91075795953709, 3.654152885361009, 3.4492782985609645, 3.320244733839166,
    3.224575052047029, 3.14788928951715, 3.083526132001233, 3.0278377917686354,
    2.978603279880845, 2.9343668672078542, 2.894121053612348, 2.8571387308721325,
    2.822877396825325, 2.7909211740007858, 2.7609440052788226, 2.732685359042827,
    2.705933656121858, 2.680514643284522, 2.6562830375755024, 2.6331163936303246,
    2.6109105184875485, 2.589575986706995, 2.5690354526805366, 2.5492215503234608,
    2.530075232158517, 2.5115444416253423, 2.4935830412696807, 2.4761499396691433,
    2.4592083743333113, 2.4427253181989568, 2.426670984935726, 2.4110184138996855,
    2.3957431197804806, 2.380822795170626, 2.3662370567158186, 2.35196722737766,
    2.3379961487950314, 2.324308018869623, 2.31088825059985, 2.2977233489013296,
    2.284800802722946, 2.272108990226824, 2.259637095172218, 2.2473750329458078,
    2.235313384928328, 2.2234433400909057, 2.2117566428825444, 2.200245546609648,
    2.1889027716247207, 2.1777214677386416, 2.166695180352646, 2.1558178198750633,
    2.1450836340462036, 2.13448718284432, 2.1240233156878157, 2.113687150684934,
    2.103474055713147, 2.0933796311370503, 2.083399693996552, 2.0735302635169788,
    2.0637675478099564, 2.054107931648865, 2.044547965215733, 2.0350843537278087,
    2.025713947862033, 2.0164337349043717, 2.007240830558685, 1.9981324713565642,
    1.9891060076155713, 1.9801588968985984, 1.9712886979317696, 1.962493064942462,
    1.953769742382734, 1.945116560006754, 1.936531428273759, 1.9280123340507183,
    1.9195573365912288, 1.9111645637692822, 1.9028322085484464, 1.89455852566871,
    1.8863418285347764, 1.8781804862909777, 1.8700729210692368, 1.8620176053976323,
    1.8540130597581481, 1.8460578502831198, 1.8381505865807286, 1.8302899196806666,
    1.8224745400917832, 1.8147031759641676, 1.8069745913486934, 1.7992875845475802,
    1.79164098655001, 1.7840336595472763, 1.776464495522345, 1.768932414909078,
    1.7614363653167067, 1.753975320315455, 1.746548278279493, 1.739154261283669,
    1.7317923140507072, 1.7244615029457757, 1.7171609150155407, 1.709889657069006,
    1.702646854797614, 1.6954316519322385, 1.6882432094348587, 1.6810807047228233,
    1.6739433309237604, 1.6668302961592867, 1.6597408228557895, 1.6526741470806485,
    1.6456295179023603, 1.6386061967731111, 1.631603456932422, 1.6246205828305684,
    1.6176568695705342, 1.6107116223673337, 1.603784156023583, 1.5968737944202613,
    1.5899798700216485, 1.5831017233934714, 1.5762387027333329, 1.5693901634125345,
    1.5625554675284397, 1.555733983466555, 1.5489250854715355, 1.5421281532263476,
    1.5353425714388431, 1.5285677294350246, 1.521803020758293, 1.5150478427739924,
    1.508301596278572, 1.5015636851127065, 1.4948335157777184, 1.4881104970546544,
    1.4813940396253757, 1.4746835556950255, 1.467978458615231, 1.4612781625074078,
    1.4545820818855233, 1.4478896312776697, 1.441200224845798, 1.4345132760029464,
    1.4278281970272904, 1.4211443986723231, 1.4144612897724647, 1.4077782768433715,
    1.4010947636762026, 1.3944101509250713, 1.3877238356868846, 1.381035211072742,
    1.3743436657700305, 1.367648583594318, 1.3609493430301018, 1.3542453167594306,
    1.3475358711773593, 1.3408203658931521, 1.3340981532160836, 1.3273685776246247,
    1.32063097521773, 1.313884673146869, 1.3071289890273539, 1.3003632303274337,
    1.2935866937335176, 1.2867986644897864, 1.2799984157103332, 1.2731852076618437,
    1.2663582870146883, 1.2595168860601442, 1.2526602218912979, 1.245787495544998,
    1.2388978911020274, 1.231990574742445, 1.225064693752808, 1.2181193754817266,
    1.2111537262399112, 1.2041668301405601, 1.197157747875586, 1.1901255154228016,
    1.1830691426787607, 1.1759876120114898, 1.1688798767268338, 1.1617448594415742,
    1.1545814503558518, 1.1473885054167339, 1.1401648443639958, 1.132909248648337,
    1.1256204592112944, 1.118297174115063, 1.1109380460092495, 1.1035416794202682,
    1.0961066278476035, 1.0886313906495142, 1.0811144096988894, 1.0735540657878717,
    1.0659486747575067, 1.0582964833260065, 1.0505956645862071, 1.0428443131393705,
    1.0350404398286053, 1.0271819660307513, 1.0192667174605292, 1.0112924174349784,
    1.0032566795395914, 0.9951569996299431, 0.9869907470938463, 0.9787551552889378,
    0.9704473110588646, 0.9620641432176052, 0.9536024098755727, 0.9450586844625711,
    0.9364293402808969, 0.9277105333962348, 0.918898183643735, 0.909987953490769,
    0.9009752244551745, 0.8918550707267924, 0.8826222295789101, 0.8732710680824946,
    0.8637955455468269, 0.8541891710015606, 0.8444449549024237, 0.8345553540795188,
    0.8245122087452886, 0.8143066701280643, 0.8039291169826649, 0.7933690588331528,
    0.7826150232995888, 0.7716544242167394, 0.7604734064220832, 0.7490566620095817,
    0.7373872114258386, 0.7254461409013035, 0.7132122851820227, 0.7006618410975844,
    0.6877678927862577, 0.6744998228274365, 0.660822574234206, 0.6466957148843889,
    0.6320722363750246, 0.6168969899962355, 0.6011046177439404, 0.5846167660937223,
    0.567338257040473, 0.5491517023130268, 0.5299097206464951, 0.5094233295859334,
    0.48744396612175434, 0.46363433677176324, 0.43751840218666266, 0.40838913458800075,
    0.3751213328504657, 0.33573751918045946, 0.2861745917472605, 0.2152418959132738,
    0.0,
)


def layer_edges() -> tuple[float, ...]:
    """The 257 layer edges x_0..x_256 of the ziggurat (see ``LAYER_EDGES``)."""
    f = lambda x: math.exp(-0.5 * x * x)  # noqa: E731
    xs = [ZIGGURAT_V / f(ZIGGURAT_R), ZIGGURAT_R]
    for _ in range(254):
        xs.append(math.sqrt(-2.0 * math.log(f(xs[-1]) + ZIGGURAT_V / xs[-1])))
    return tuple(xs) + (0.0,)


def _tables() -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(k, w, f) per layer i: accept the 52-bit abscissa j at once if j < k_i; x = j w_i;
    f_i = exp(-x_i^2 / 2) (f_256 = 1) for the wedge test."""
    x = np.array(LAYER_EDGES)
    k = np.floor(x[1:] / x[:-1] * 2.0**52).astype(np.uint64)  # IEEE division: the same everywhere
    w = x[:-1] * 2.0**-52
    f = np.exp(-0.5 * x * x)
    return k, w, f


ZIG_K, ZIG_W, ZIG_F = _tables()
_M8 = np.uint64(0xFF)
_M52 = np.uint64(0x000FFFFFFFFFFFFF)
_U1, _U8, _U11, _U17, _U23, _U41, _U45 = (np.uint64(s) for s in (1, 8, 11, 17, 23, 41, 45))
_U64_45, _U64_23 = np.uint64(64 - 45), np.uint64(64 - 23)
_TO_UNIT = 2.0**-53
_SIGN = np.array([1.0, -1.0])


def block_state(seed: int, block: int, stream: tuple[int, ...] = ()) -> np.ndarray:
    """xoshiro256++ state (4 uint64) of block ``block``: from
    ``SeedSequence(seed, spawn_key=(*stream, block))``; never all zero."""
    s = SeedSequence(seed, spawn_key=(*stream, block)).generate_state(4, np.uint64)
    if not s.any():  # the one state xoshiro cannot leave (probability 2^-256)
        s[0] = 1
    return s


@njit(inline="always")
def _next(s0, s1, s2, s3):
    """One xoshiro256++ step: (64 random bits, new state)."""
    a = s0 + s3
    out = ((a << _U23) | (a >> _U64_23)) + s0
    t = s1 << _U17
    s2 ^= s0
    s3 ^= s1
    s1 ^= s2
    s0 ^= s3
    s2 ^= t
    s3 = (s3 << _U45) | (s3 >> _U64_45)
    return out, s0, s1, s2, s3


@njit(inline="always")
def _unit(bits):
    """A uniform in [0, 1) from the top 53 bits."""
    return np.float64(np.int64(bits >> _U11)) * _TO_UNIT


@njit(inline="always")
def _normal(s0, s1, s2, s3):
    """One standard normal by the ziggurat: (z, new state)."""
    while True:
        r, s0, s1, s2, s3 = _next(s0, s1, s2, s3)
        i = np.intp(r & _M8)
        r >>= _U8
        sign = _SIGN[np.intp(r & _U1)]  # a table, not a branch: the sign is a coin toss
        j = (r >> _U1) & _M52
        x = np.float64(np.int64(j)) * ZIG_W[i]
        if j < ZIG_K[i]:  # inside the layer's rectangle under the curve: ~98.8 % of draws
            return sign * x, s0, s1, s2, s3
        if i == 0:  # the tail beyond r (Marsaglia 1964)
            while True:
                u, s0, s1, s2, s3 = _next(s0, s1, s2, s3)
                v, s0, s1, s2, s3 = _next(s0, s1, s2, s3)
                xt = -math.log(1.0 - _unit(u)) / ZIGGURAT_R
                yt = -math.log(1.0 - _unit(v))
                if yt + yt > xt * xt:
                    break
            x = ZIGGURAT_R + xt
            return sign * x, s0, s1, s2, s3
        u, s0, s1, s2, s3 = _next(s0, s1, s2, s3)  # the wedge between the rectangle and the curve
        if ZIG_F[i] + _unit(u) * (ZIG_F[i + 1] - ZIG_F[i]) < math.exp(-0.5 * x * x):
            return sign * x, s0, s1, s2, s3


@njit(nogil=True, inline="always")
def _fill(s0, s1, s2, s3, out, m):
    """out[:m] <- standard normals: (new state)."""
    for t in range(m):
        z, s0, s1, s2, s3 = _normal(s0, s1, s2, s3)
        out[t] = z
    return s0, s1, s2, s3


@njit(nogil=True, cache=True)
def standard_normals(state, out):
    """out (n, k), C-contiguous, <- standard normals, sample by sample, factor by factor (the
    draw order of ``linear_normal_block``); ``state`` (4 uint64) is advanced."""
    s0, s1, s2, s3 = _fill(state[0], state[1], state[2], state[3], out.reshape(out.size), out.size)
    state[0], state[1], state[2], state[3] = s0, s1, s2, s3


CHUNK = 64  # samples whose normals are drawn before they are weighted (a few kB: stays in L1)


@njit(nogil=True, cache=True)
def linear_normal_block(state, n, weights, offset, out):
    """out[i] = offset + sum_j z_ij weights[j] (in order j), z standard normal (drawn in the
    order of ``standard_normals``): the linear model with sigma folded into the weights,
    y = c + sum (S_j sigma_j) z_j; ``state`` is advanced.

    The normals of CHUNK samples are drawn first, then weighted column by column: drawing has
    no floating-point chain through the sum, and the weighting runs in SIMD over samples."""
    k = weights.size
    z = np.empty(CHUNK * k)
    s0, s1, s2, s3 = state[0], state[1], state[2], state[3]
    for a in range(0, n, CHUNK):
        m = min(CHUNK, n - a)
        s0, s1, s2, s3 = _fill(s0, s1, s2, s3, z, m * k)
        y = out[a:a + m]
        y[:] = offset
        for j in range(k):
            wj = weights[j]
            for i in range(m):
                y[i] += z[i * k + j] * wj
    state[0], state[1], state[2], state[3] = s0, s1, s2, s3


# --- stream sets: one xoshiro256++ state per factor, for the per-unit samplers -------------------
# The contact, elastic and transmission-error sources draw every factor from a stream of its own
# (a factor can be redrawn alone, global sensitivity). A stream set is a (k, 4) uint64 array, a
# state per row; ``stream_normal(states, f)`` and ``stream_uniform(states, f)`` draw from row f
# and advance it in place (~2 ns a number against ~17 ns through numba's Generator).

def stream_states(seeds: list[SeedSequence]) -> np.ndarray:
    """(len(seeds), 4) xoshiro256++ states, one per SeedSequence (never all zero)."""
    out = np.empty((len(seeds), 4), dtype=np.uint64)
    for i, s in enumerate(seeds):
        out[i] = s.generate_state(4, np.uint64)
        if not out[i].any():
            out[i, 0] = 1
    return out


def states_from_generators(generators) -> np.ndarray:
    """(len(generators), 4) states seeded by 4 words of each numpy Generator (the Sobol-type
    redraws of global sensitivity hand a model one Generator per input)."""
    out = np.empty((len(generators), 4), dtype=np.uint64)
    for i, g in enumerate(generators):
        out[i] = g.integers(0, 2**64, size=4, dtype=np.uint64, endpoint=False)
        if not out[i].any():
            out[i, 0] = 1
    return out


@njit(nogil=True, cache=True)
def stream_normal(states, f):
    """A standard normal from stream f of ``states`` (advanced in place). A call, not inlined: a
    kernel drawing scalars at many places would otherwise compile the ziggurat at each (tens of
    seconds of compilation for a few ns per draw)."""
    z, s0, s1, s2, s3 = _normal(states[f, 0], states[f, 1], states[f, 2], states[f, 3])
    states[f, 0], states[f, 1], states[f, 2], states[f, 3] = s0, s1, s2, s3
    return z


@njit(nogil=True, cache=True)
def stream_normals(states, f, p0, p1, lo, hi, out, m):
    """out[:m] <- p0 + p1 z from stream f, each z redrawn until the value lies in [lo, hi] (+-inf:
    a plain normal): the same numbers as m calls of ``stream_normal``, with the state held in
    registers through the loop (a stream's per-element draws in one pass)."""
    s0, s1, s2, s3 = states[f, 0], states[f, 1], states[f, 2], states[f, 3]
    for i in range(m):
        while True:
            z, s0, s1, s2, s3 = _normal(s0, s1, s2, s3)
            x = p0 + p1 * z
            if lo <= x <= hi:
                break
        out[i] = x
    states[f, 0], states[f, 1], states[f, 2], states[f, 3] = s0, s1, s2, s3


@njit(nogil=True, inline="always")
def stream_uniform(states, f):
    """A uniform in [0, 1) from stream f of ``states`` (advanced in place)."""
    r, s0, s1, s2, s3 = _next(states[f, 0], states[f, 1], states[f, 2], states[f, 3])
    states[f, 0], states[f, 1], states[f, 2], states[f, 3] = s0, s1, s2, s3
    return _unit(r)
