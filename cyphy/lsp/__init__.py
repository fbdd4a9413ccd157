"""``cyphy lsp``: a Language Server Protocol server for RoboSim text (``.pm``, ``.rst``,
``.rsm``), an edge of the package like :mod:`cyphy.cli`.

:mod:`cyphy.lsp.index` and :mod:`cyphy.lsp.features` hold what an editor asks, as plain data
over the front end's results (no protocol types), so they are tested without a client;
:mod:`cyphy.lsp.server` turns them into LSP messages with ``pygls`` and ``lsprotocol``, which
are imported only when the server starts (``pip install cyphy[lsp]``).
"""
