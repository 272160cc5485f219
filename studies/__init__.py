"""Assembly configurations, the FE -> analytic pipeline, studies, diagnosis and the CLI."""
