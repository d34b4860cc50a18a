"""viewer/pictures/wrap.py: text in rows that fit, broken where its phrases meet."""
from viewer.pictures import wrap


class TenPixelFont:
    """A font 10 px a character, for phrase_rows."""
    def size(self, text):
        return 10 * len(text), 12


def test_phrase_rows_break_between_phrases_before_words():
    """A line that does not fit breaks where its phrases meet, the strongest break first: between
    the key hints (three spaces), after a semicolon, before a parenthesis, after a comma, after a
    colon; only a phrase still too wide breaks between words. A line that fits stays whole."""
    font, rows = TenPixelFont(), wrap.phrase_rows
    assert rows(font, "CCD bound alpha_CCD = 0.71 (black ring: x^i + alpha_CCD p)", 400) == [
        "CCD bound alpha_CCD = 0.71", "(black ring: x^i + alpha_CCD p)"]     # not "..." / "p)"
    assert rows(font, "space: play   r: restart   q, Esc: quit", 250) == [
        "space: play   r: restart", "q, Esc: quit"]
    assert rows(font, "grey: x^i; blue: x^i + alpha p; red: p", 330) == [
        "grey: x^i; blue: x^i + alpha p;", "red: p"]
    assert rows(font, "the slope: 8.99 mm below x^i, out of frame", 200) == [
        "the slope:", "8.99 mm below x^i,", "out of frame"]             # not "below x^i," alone
    assert rows(font, "a_very_long_word fits", 50) == ["a_very_long_word", "fits"]
    assert rows(font, "fits (whole)", 120) == ["fits (whole)"]
