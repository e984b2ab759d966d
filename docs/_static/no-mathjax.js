/* MathJax is not loaded: the site downloads nothing. Formulas are text and images. */
