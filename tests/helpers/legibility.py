"""What a class at the back of a room sees: the text the window and the frames draw (its size, its
colour), the contrast of a colour against white, the distance between two colours, and whether a
legend's swatch sits on its label's row. Shared by test_window.py, test_viewer_outputs.py and
test_newton_view.py."""
import numpy as np

WHITE = (255, 255, 255)


def record_text(monkeypatch):
    """From now on, every non-empty text pygame's fonts render, as (text, cap height in px, colour):
    pygame.font.Font replaced by a subclass that notes what it draws. The cap height is measured in
    pixels (the rows of ink of a rendered H), not taken from the font's metrics."""
    import pygame
    drawn = []

    class RecordingFont(pygame.font.Font):
        def render(self, text, antialias, color, *rest, **kw):
            if text.strip():
                if not hasattr(self, "cap"):
                    self.cap = ink_rows(super().render("H", False, (0, 0, 0), WHITE))
                drawn.append((text, self.cap, tuple(color)[:3]))
            return super().render(text, antialias, color, *rest, **kw)

    monkeypatch.setattr(pygame.font, "Font", RecordingFont)
    return drawn


def ink_rows(surface):
    """How many rows of `surface` (dark text on white) hold ink."""
    import pygame
    pixels = pygame.surfarray.array3d(surface)                      # [x, y, rgb]
    return int((pixels < 128).all(axis=2).any(axis=0).sum())


def relative_luminance(color):
    """WCAG 2.x relative luminance of an sRGB colour (0 black .. 1 white)."""
    c = np.asarray(color, float) / 255.0
    linear = np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)
    return float(linear @ [0.2126, 0.7152, 0.0722])


def contrast_ratio(a, b=WHITE):
    """WCAG 2.x contrast ratio (L1 + 0.05) / (L2 + 0.05), 1 to 21; text needs 4.5 (level AA)."""
    la, lb = sorted((relative_luminance(a), relative_luminance(b)), reverse=True)
    return (la + 0.05) / (lb + 0.05)


def cielab(color):
    """CIE 1976 L*a*b* of an sRGB colour (D65 white)."""
    c = np.asarray(color, float) / 255.0
    linear = np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)
    srgb_to_xyz = np.array([[0.4124, 0.3576, 0.1805],
                            [0.2126, 0.7152, 0.0722],
                            [0.0193, 0.1192, 0.9505]])
    xyz = srgb_to_xyz @ linear
    t = xyz / [0.95047, 1.0, 1.08883]
    f = np.where(t > (6 / 29) ** 3, np.cbrt(t), t / (3 * (6 / 29) ** 2) + 4 / 29)
    return np.array([116 * f[1] - 16, 500 * (f[0] - f[1]), 200 * (f[1] - f[2])])


def delta_e(a, b):
    """CIE 1976 colour difference: the distance between two colours in L*a*b* (about 2.3 is just
    noticeable side by side; tens tell two colours apart at a glance)."""
    return float(np.linalg.norm(cielab(a) - cielab(b)))


def swatch_and_label_rows(pixels, color, bottom):
    """Where the legend swatch of `color` (the only pixels of that colour in the rows above
    `bottom`, left of the text) and its label are: (swatch top, swatch bottom, label top, label
    bottom, gap), the label being the band of rows with dark ink to the swatch's right that holds
    the swatch's middle row, and gap the pixels between the swatch and the label's first ink.
    `pixels` is [x, y, rgb]."""
    mask = np.all(pixels[:, :bottom] == color, axis=2)
    xs, ys = np.nonzero(mask)
    assert len(xs), f"no swatch of {color}"
    right, top, low = xs.max(), ys.min(), ys.max()
    dark = (pixels[right + 1:, :bottom] < 128).all(axis=2)         # [x, y], black text
    inked = dark.any(axis=0)
    middle = (top + low) // 2
    assert inked[middle], f"no label on the row of the swatch of {color}"
    first = last = middle
    while first > 0 and inked[first - 1]:
        first -= 1
    while last + 1 < len(inked) and inked[last + 1]:
        last += 1
    gap = int(np.nonzero(dark[:, first:last + 1].any(axis=1))[0].min())
    return int(top), int(low), first, last, gap
