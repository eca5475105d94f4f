"""Report rendering: translation, number formatting, figures, HTML and PDF.

Nothing here computes physics; it formats what the stages computed.
"""
