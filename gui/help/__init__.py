"""The offline manual: pages made from the README's sections (with its pictures), a getting-started
page, a list of shortcuts and context help for the tools and docks, shown in the app's help window.

``manual`` and ``topics`` are Qt-free (the pages as Markdown); ``window`` shows them.
"""
