"""Widgets of the menu screens: menu text, the Fig. 2-8 and Fig. 4-2 readouts, the prompt line."""
