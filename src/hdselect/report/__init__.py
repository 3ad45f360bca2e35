"""What a user reads: terminal tables, JSON and CSV, figures and the HTML report.

The modules format results; none computes a number a result does not already hold.
`terminal` and `tables` print, `export` writes JSON and CSV, `figures` and `html`
draw and write the report, `provenance` records where a result came from.
"""
