"""Report writers: files, figures and Markdown sections built from study results."""
