"""Bad input to the energy functions raises ValueError naming the argument; no NaN comes back."""
import inspect
import re

import numpy as np
import pytest

import BarrierEnergy
import FrictionEnergy
import HandEnergy
import GravityEnergy
import InertiaEnergy
import MassSpringEnergy
import square_mesh

X, E = square_mesh.generate(1.0, 2)
L2 = np.einsum("ij,ij->i", X[E[:, 0]] - X[E[:, 1]], X[E[:, 0]] - X[E[:, 1]])
N, O = np.array([0.0, 1.0]), np.array([0.0, 0.0])   # the lower half of the square is below
W = np.full(len(X), 0.5)
NAN_X = X.copy()
NAN_X[3, 1] = np.nan


def spring(x=X, e=E, l2=L2, k=1.0):
    return lambda f: f(x, e, l2, k)


def barrier(x=X, n=N, o=O, w=W, **kw):
    return lambda f: f(x, n, o, w, **kw)


def friction(v=X * 0, ml=W, hhat=0.01, n=N, **kw):
    return lambda f: f(v, ml, hhat, n, **kw)


CASES = [
    (MassSpringEnergy, spring(x=X[:, :1]), "x must have shape"),
    (MassSpringEnergy, spring(x=NAN_X), "x has a non-finite value nan at node 3"),
    (MassSpringEnergy, spring(e=E + 100), "e has node index"),
    (MassSpringEnergy, spring(e=E.astype(float)), "e must hold integer"),
    (MassSpringEnergy, spring(l2=L2[:-1]), "l2 must have one value per edge"),
    (MassSpringEnergy, spring(k=np.ones(3)), "k must have one value per edge"),
    (MassSpringEnergy, spring(k=np.inf), "k has a non-finite value inf"),
    (MassSpringEnergy, spring(l2=0 * L2), "l2 must be > 0 at every edge, got 0.0 at edge 0"),
    (InertiaEnergy, lambda f: f(X, X[:-1], np.ones(len(X))), "x_tilde must have the shape"),
    (InertiaEnergy, lambda f: f(X, X, -np.ones(len(X))), "m must be > 0"),
    (GravityEnergy, lambda f: f(X, np.ones(2)), "m must have one value per node"),
    (GravityEnergy, lambda f: f(X, np.ones(len(X)), (0, np.nan)), "g must be finite"),
    (BarrierEnergy, barrier(), "node 0 is at distance"),                       # below the slope
    (BarrierEnergy, barrier(o=[0.0, -0.5]), "distance 0 <= 0"),               # touching it
    (BarrierEnergy, barrier(w=W[:2]), "contact_area must have one value per node"),
    (BarrierEnergy, barrier(n=[0.0, 2.0]), "n must be a unit vector"),
    (BarrierEnergy, barrier(o=[0.0, -2.0], dhat=0.0), "dhat must be a finite number > 0"),
    (BarrierEnergy, barrier(o=[0.0, -2.0], kappa=np.nan), "kappa must be a finite number > 0"),
    (FrictionEnergy, friction(ml=W[:3]), "mu_lambda must have one value per node"),
    (FrictionEnergy, friction(ml=-W), "mu_lambda must be >= 0"),
    (FrictionEnergy, friction(hhat=0.0), "hhat must be a finite number > 0"),
    (FrictionEnergy, friction(epsv=-1.0), "epsv must be a finite number > 0"),
    (FrictionEnergy, friction(v=NAN_X), "v has a non-finite value"),
]


@pytest.mark.parametrize("module, call, message", CASES, ids=[c[2][:30] for c in CASES])
@pytest.mark.parametrize("kind", ["val", "grad", "hess"])
def test_bad_input_raises_value_error(module, call, message, kind):
    with pytest.raises(ValueError, match=re.escape(message)):
        call(getattr(module, kind))


def test_ccd_and_mu_lambda_bad_input():
    with pytest.raises(ValueError, match="p must have the shape of x"):
        BarrierEnergy.init_step_size(X, N, [0, -2.0], X[:2])
    with pytest.raises(ValueError, match="mu must be a finite number >= 0, got -0.1"):
        BarrierEnergy.compute_mu_lambda(X, N, [0, -2.0], W, -0.1)
    with pytest.raises(ValueError, match="node 0 is at distance"):
        BarrierEnergy.compute_mu_lambda(X, N, O, W, 0.1)
    with pytest.raises(ValueError, match="side_len must be a finite number > 0, got 0"):
        square_mesh.generate(0.0, 4)
    with pytest.raises(ValueError, match="n_seg must be a whole number >= 1, got 2.5"):
        square_mesh.generate(1.0, 2.5)


@pytest.mark.parametrize("call", [
    lambda: BarrierEnergy.grad(np.array([[0.0, 1e-320]]), [0.0, 1.0], [0.0, 0.0], [1.0]),
    lambda: BarrierEnergy.hess(np.array([[0.0, 1e-160]]), [0.0, 1.0], [0.0, 0.0], [1.0]),
], ids=["barrier grad d=1e-320", "barrier hess d=1e-160"])
def test_overflow_beyond_float64_raises_instead_of_nan(call):
    with np.errstate(all="ignore"):
        with pytest.raises(ValueError, match="overflowed to a non-finite value"):
            call()


@pytest.mark.parametrize("kind", ["val", "grad", "hess"])
@pytest.mark.parametrize("epsv", [1e-310, 1e308])
def test_eps_v_whose_square_leaves_float64_is_refused(kind, epsv):
    """f_hess_term is -1/max(||vbar||, eps_v)^2: 1/eps_v^2 overflows float64 for eps_v below
    7.5e-155, eps_v^2 above 1.3e154: refused, the range named."""
    v = np.full((2, 2), 1e-320)
    said = re.escape(f"epsv must be in [1e-150, 1e+150] m/s (eps_v^2 in float64), got {epsv}")
    with pytest.raises(ValueError, match=said):
        getattr(FrictionEnergy, kind)(v, np.ones(2), 0.01, [0.0, 1.0], epsv=epsv)


def test_tiny_eps_v_still_exact_where_representable():
    """The mollifier is written in ||vbar||/eps_v, so a tiny eps_v loses nothing until a result
    overflows (the lecture's (-||vbar|| + 2 eps_v)/(eps_v eps_v) would overflow at eps_v =
    1e-160)."""
    f1_div = FrictionEnergy.f1_div_vbarnorm(np.array([0.0, 5e-161]), 1e-160)
    assert f1_div == pytest.approx([2e160, 1.5e160])
    assert FrictionEnergy.f0(np.array([0.0]), 1e-160, 0.01) == pytest.approx([1e-162 / 3])
    # the Hessian there is mu_lambda (f1/||vbar|| + f_hess_term ||vbar||) / hhat along the tangent:
    # 2/eps_v / hhat = 2e152 at ||vbar|| ~ 1e-170, finite
    v = np.full((2, 2), 1e-170)
    rows, cols, vals = FrictionEnergy.hess(v, np.ones(2), 0.01, [0.0, 1.0], epsv=1e-150)
    assert vals.max() == pytest.approx(2e152, rel=1e-6) and np.isfinite(vals).all()


def test_ccd_refuses_a_start_below_the_slope():
    with pytest.raises(ValueError, match="node 0 is at distance -1 <= 0"):
        BarrierEnergy.init_step_size(np.array([[0.0, -1.0]]), N, O, np.ones((1, 2)))


# ---- what is not an array of real numbers (issue 25, item 7) -------------------------------------

# every public argument of each energy, at values each accepts (the slope below every node)
ARGS = {
    InertiaEnergy: dict(x=X, x_tilde=X, m=np.ones(len(X))),
    MassSpringEnergy: dict(x=X, e=E, l2=L2, k=1.0),
    GravityEnergy: dict(x=X, m=np.ones(len(X)), g=(0.0, -9.81)),
    BarrierEnergy: dict(x=X, n=N, o=[0.0, -0.55], contact_area=W),
    FrictionEnergy: dict(v=X * 0, mu_lambda=W, hhat=0.01, n=N),
}


def not_real(value):
    """`value` made complex (with zero imaginary parts: the old checks dropped them silently), text
    that float() would parse, booleans, and Python objects that are no number (an object array of
    numbers converts, test_bad_input_limits): each is no real number."""
    if np.ndim(value) == 0:
        return [complex(value), np.complex128(value), str(value), True, np.True_,
                np.array(1.0 + 0j), None]
    a = np.asarray(value)
    objects = a.astype(object)
    objects.flat[0] = str(objects.flat[0])
    return [a.astype(complex), a.astype(str), a.astype(bool), objects, a.tolist() + [[1j, 0]]]


NOT_REAL = [(module, name, bad) for module, args in ARGS.items() for name, value in args.items()
            for bad in not_real(value)]


def kind_of(b):
    return b.dtype if isinstance(b, np.ndarray) else type(b).__name__


@pytest.mark.parametrize("module, name, bad", NOT_REAL,
                         ids=[f"{m.__name__}-{n}-{kind_of(b)}" for m, n, b in NOT_REAL])
@pytest.mark.parametrize("kind", ["val", "grad", "hess"])
def test_an_argument_that_is_no_real_number_is_refused_by_name(module, name, bad, kind):
    getattr(module, kind)(**ARGS[module])       # the good arguments pass
    with pytest.raises(ValueError, match=f"^{name} must "):
        getattr(module, kind)(**{**ARGS[module], name: bad})


@pytest.mark.parametrize("name, value", [("k", 10 ** 400), ("l2", -10 ** 400)])
def test_an_int_beyond_float64_is_refused_by_name(name, value):
    message = rf"^{name} must be a number, got -?1\.00e\+400, beyond float64's range"
    with pytest.raises(ValueError, match=message):
        MassSpringEnergy.val(**{**ARGS[MassSpringEnergy], name: value})


@pytest.mark.parametrize("module, name, must_be", [(InertiaEnergy, "m", "> 0"),
                                                   (MassSpringEnergy, "l2", "> 0"),
                                                   (FrictionEnergy, "mu_lambda", ">= 0")])
def test_the_first_item_out_of_range_is_named(module, name, must_be):
    """One check (utils.check_per_item's must_be) for the masses, the squared rest lengths and
    mu lambda: the first item that breaks it, by index; zero is refused only by must_be > 0."""
    good = np.asarray(ARGS[module][name], dtype=float)
    bad = good.copy()
    bad[[3, 5]] = -1.0
    what = "edge" if module is MassSpringEnergy else "node"
    for kind in ("val", "grad", "hess"):
        message = rf"^{name} must be {must_be} at every {what}, got -1.0 at {what} 3$"
        with pytest.raises(ValueError, match=message):
            getattr(module, kind)(**{**ARGS[module], name: bad})
    zero = good.copy()
    zero[4] = 0.0
    if must_be == "> 0":
        with pytest.raises(ValueError, match=rf"got 0.0 at {what} 4$"):
            module.val(**{**ARGS[module], name: zero})
    else:
        module.val(**{**ARGS[module], name: zero})


# ---- results beyond float64 from finite arguments: refused the same way by all five --------------

BIG = 1e200
OVERFLOWS = [      # (module, kind, arguments whose result overflows)
    (InertiaEnergy, "val", dict(x=BIG * X, x_tilde=-BIG * X, m=np.ones(len(X)))),
    (InertiaEnergy, "grad", dict(x=BIG * X, x_tilde=-BIG * X, m=np.full(len(X), BIG))),
    (MassSpringEnergy, "val", dict(x=BIG * X, e=E, l2=L2, k=1.0)),
    (MassSpringEnergy, "grad", dict(x=1e308 * X, e=E, l2=L2, k=1.0)),         # the NaN
    (MassSpringEnergy, "hess", dict(x=BIG * X, e=E, l2=L2, k=1.0)),
    (GravityEnergy, "val", dict(x=X + 1.0, m=np.full(len(X), BIG), g=(0.0, -BIG))),
    (GravityEnergy, "grad", dict(x=X, m=np.full(len(X), BIG), g=(0.0, -BIG))),
    (BarrierEnergy, "val", dict(x=X, n=N, o=[0.0, -0.505], contact_area=np.full(len(X), 1e308),
                                kappa=1e308)),
    (BarrierEnergy, "grad", dict(x=np.array([[0.0, 1e-320]]), n=N, o=O, contact_area=[1.0])),
    (BarrierEnergy, "hess", dict(x=np.array([[0.0, 1e-160]]), n=N, o=O, contact_area=[1.0])),
    (FrictionEnergy, "val", dict(v=X + 1e10, mu_lambda=np.full(len(X), 1e308), hhat=1.0, n=N)),
    (FrictionEnergy, "grad", dict(v=np.full((1, 2), 5e-4), mu_lambda=[1e308], hhat=0.01,
                                  n=[1.0, 0.0])),
    (FrictionEnergy, "hess", dict(v=np.zeros((1, 2)), mu_lambda=[1e308], hhat=0.01, n=N)),
]


@pytest.mark.parametrize("module, kind, args", OVERFLOWS,
                         ids=[f"{m.__name__}.{k}" for m, k, _ in OVERFLOWS])
def test_a_result_beyond_float64_is_refused_never_returned(module, kind, args):
    """Finite arguments the checks accept, whose kernel's result is not finite (inf or NaN): the
    public function raises the one utils.finite_result error, naming the function and the module's
    arguments."""
    public = {p.name: p.default
              for p in inspect.signature(getattr(module, kind)).parameters.values()}
    names = inspect.signature(module._check).parameters
    checked = module._check(*[args.get(name, public[name]) for name in names])
    with np.errstate(all="ignore"):
        result = getattr(module, f"{kind}_kernel")(*checked)
        assert not np.isfinite(result[1] if kind == "hess" else result).all()
        with pytest.raises(ValueError) as info:
            getattr(module, kind)(**args)
    assert str(info.value) == (f"{module.__name__}.{kind} overflowed to a non-finite value: its "
                               f"arguments are beyond float64's range (check {module.ARGUMENTS})")


@pytest.mark.parametrize("side_len, n_seg, message", [
    (1.0, "4", "n_seg must be a whole number >= 1, got '4'"),
    (1.0, 4 + 0j, r"n_seg must be a whole number >= 1, got \(4\+0j\)"),
    (1.0, True, "n_seg must be a whole number >= 1, got True"),
    (1.0, 10 ** 400, r"n_seg must be a whole number >= 1, got 1\.00e\+400, beyond float64's "
                     r"range"),
    (10 ** 400, 4, r"side_len must be a finite number > 0, got 1\.00e\+400, beyond float64's "
                   r"range"),
    ("1", 4, "side_len must be a finite number > 0, got '1'"),
    (np.array([1.0]), 4, r"side_len must be a finite number > 0, got array\(\[1\.\]\)"),
], ids=["'4'", "4+0j", "True", "10**400", "side 10**400", "side '1'", "side array"])
def test_mesh_refuses_what_is_no_number(side_len, n_seg, message):
    with pytest.raises(ValueError, match=f"^{message}$"):
        square_mesh.generate(side_len, n_seg)


HELD, TARGET = np.array([6, 7, 8]), X[6:] + [0.0, -0.1]


def hand(x=X, nodes=HELD, target=TARGET, k_hand=2000.0):
    return lambda f: f(x, nodes, target, k_hand)


@pytest.mark.parametrize("call, message", [
    (hand(x=NAN_X), "x has a non-finite value nan at node 3"),
    (hand(nodes=HELD + 7), "nodes has node index 13 outside [0, 9)"),
    (hand(nodes=HELD.astype(float)), "nodes must be a 1-D array of integer node indices"),
    (hand(nodes=np.array([6, 6, 8])), "nodes must not hold a node twice"),
    (hand(target=TARGET[:2]), "target must have shape (3, 2)"),
    (hand(k_hand=np.ones(2)), "k_hand must have one value per held node (3)"),
    (hand(k_hand=-1.0), "k_hand must be >= 0, got -1.0 at held node 0"),
])
@pytest.mark.parametrize("kind", ["val", "grad", "hess"])
def test_bad_input_to_the_hand_raises_value_error(call, message, kind):
    with pytest.raises(ValueError, match=re.escape(message)):
        call(getattr(HandEnergy, kind))


def test_a_mu_per_node_is_checked():
    # every node above the ground, the bottom row within dhat
    x = X + [0.0, 0.505]
    with pytest.raises(ValueError, match="mu must have one value per node"):
        BarrierEnergy.compute_mu_lambda(x, N, O, W, np.ones(3))
    with pytest.raises(ValueError, match="mu must be >= 0 at every node, got -0.5 at node 4"):
        BarrierEnergy.compute_mu_lambda(x, N, O, W, np.where(np.arange(len(X)) == 4, -0.5, 0.3))
