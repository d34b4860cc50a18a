"""Central finite differences for gradient and Hessian checks.

Step: for a central difference the truncation error is O(eps^2 |f'''|) and the round-off error
O(u |f| / eps) with u = 2.2e-16, balanced at eps ~ u^(1/3) ~ 6e-6 (relative to the scale of x).
The resulting relative error is ~ u^(2/3) ~ 4e-11 for well-scaled functions; we allow 1e-6
relative to the largest entry (plus a tiny absolute floor for exact zeros), four orders of
magnitude of margin, still far below what a wrong sign (error ~ 2) or a factor of two (~ 0.5) gives.
"""
import numpy as np

RTOL = 1e-6


def fd_gradient(f, x, eps):
    """Central-difference gradient of scalar f at x (any shape)."""
    x = np.array(x, dtype=np.float64)
    g = np.zeros_like(x)
    flat_x, flat_g = x.reshape(-1), g.reshape(-1)
    for i in range(flat_x.size):
        orig = flat_x[i]
        flat_x[i] = orig + eps
        fp = f(x)
        flat_x[i] = orig - eps
        fm = f(x)
        flat_x[i] = orig
        flat_g[i] = (fp - fm) / (2 * eps)
    return g


def fd_jacobian(grad, x, eps):
    """Central-difference Jacobian of an (N, 2)-valued grad at x: (2N, 2N), DOF 2*node + axis."""
    x = np.array(x, dtype=np.float64)
    n = x.size
    J = np.zeros((n, n))
    flat = x.reshape(-1)
    for i in range(n):
        orig = flat[i]
        flat[i] = orig + eps
        gp = np.asarray(grad(x)).reshape(-1)
        flat[i] = orig - eps
        gm = np.asarray(grad(x)).reshape(-1)
        flat[i] = orig
        J[:, i] = (gp - gm) / (2 * eps)
    return J


def dense(ijv, n_dofs):
    """An IJV triplet summed into a dense matrix."""
    H = np.zeros((n_dofs, n_dofs))
    np.add.at(H, (ijv[0], ijv[1]), ijv[2])
    return H


def roundoff(values, eps):
    """Absolute round-off bound of a central difference of a function of size |values| at step eps:
    u |f| / eps with u = 2.2e-16, times 1e3 for margin. Where the derivative is exactly zero (the
    friction gradient at vbar = 0) this is the only error left, so it is the check's floor."""
    return 1e3 * 2.2e-16 * np.abs(np.asarray(values, dtype=np.float64)).max(initial=0.0) / eps


def assert_close(actual, expected, rtol=RTOL, what="", atol=0.0):
    actual, expected = np.asarray(actual), np.asarray(expected)
    scale = max(np.abs(expected).max(initial=0.0), np.abs(actual).max(initial=0.0))
    err = np.abs(actual - expected).max(initial=0.0)
    assert err <= rtol * scale + atol, \
        f"{what}: max error {err:.3e} vs scale {scale:.3e} (rtol {rtol}, atol {atol:.1e})"


def check_derivatives(val, grad, hess, x, eps, rtol=1e-6):
    """grad == FD(val) and dense(hess) == FD(grad) at x; also hess is symmetric and 2N x 2N."""
    fd = fd_gradient(val, x, eps)
    assert_close(grad(x), fd, rtol, "grad vs FD of val", roundoff(val(x), eps))
    ijv = hess(x)
    assert all(a.ndim == 1 for a in ijv) and len({len(a) for a in ijv}) == 1
    H = dense(ijv, x.size)
    assert_close(H, H.T, 1e-12, "hess symmetry")
    assert_close(H, fd_jacobian(grad, x, eps), rtol, "hess vs FD of grad", roundoff(grad(x), eps))


def check_energy(module, x, eps, *args, **hess_kw):
    """check_derivatives of module.val, grad and hess(y, *args, **hess_kw)."""
    check_derivatives(lambda y: module.val(y, *args), lambda y: module.grad(y, *args),
                      lambda y: module.hess(y, *args, **hess_kw), x, eps)
