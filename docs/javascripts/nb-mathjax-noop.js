/* Intentionally empty. mkdocs-jupyter's `custom_mathjax_url` points here instead of its default
 * (MathJax 2 from a CDN); docs/hooks/offline_site.py removes that loader from notebook pages, which
 * get MathJax 3 like every page (mkdocs.yml extra_javascript). */
