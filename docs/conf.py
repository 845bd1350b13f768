# Sphinx configuration of the yade-mss manual; built by scripts/docs.sh (warnings are errors).
import os
import sys

project = 'yade-mss'
author = 'the yade-mss developers'


def _version():
    """The CMake project's version (CMakeLists.txt): the one place it is written."""
    import re
    with open(os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', 'CMakeLists.txt')) as f:
        return re.search(r'project\(yade_mss VERSION ([0-9.]+)', f.read()).group(1)


version = release = _version()
html_title = 'yade-mss %s manual' % version
copyright = '2026, ' + author
extensions = ['sphinx.ext.autodoc', 'sphinx.ext.mathjax']
xml = os.environ.get('MSS_DOXYGEN_XML')
if xml:  # the C++ API from the public headers (doxygen's XML, through breathe)
    extensions.append('breathe')
    breathe_projects = {'mss': xml}
    breathe_default_project = 'mss'
    breathe_default_members = ('members',)
exclude_patterns = ['_build']
html_theme = 'alabaster'
html_theme_options = {'description': 'multi-sphere clumps for DEM', 'fixed_sidebar': True,
                      'page_width': '1240px', 'sidebar_width': '220px', 'body_max_width': '1000px'}  # 100 columns of code
html_static_path = ['_static']
autodoc_member_order = 'bysource'
autodoc_default_options = {'members': True, 'undoc-members': False}
# mathjax is fetched by the reader's browser; the pages read without it
mathjax_path = 'https://cdn.jsdelivr.net/npm/mathjax@3/es5/tex-mml-chtml.js'
nitpicky = False
sys.path.insert(0, os.path.dirname(__file__))


def _yref(name, rawtext, text, lineno, inliner, options={}, content=[]):
    """YADE's own docs link their classes with :yref:; here it is YADE's name in code font."""
    from docutils import nodes
    return [nodes.literal(rawtext, text)], []


def setup(app):
    app.add_role('yref', _yref)
