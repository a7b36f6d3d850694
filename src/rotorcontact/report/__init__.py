"""The paper's results reproduced: every figure and number, and an HTML report."""
