-- Drives `cyphy lsp` from Neovim's own LSP client (Neovim 0.7 or later, headless): opens
-- $CYPHY_FILE, waits for its diagnostics, asks for the definition at $CYPHY_LINE:$CYPHY_COL
-- (0-based), and writes what it got to $CYPHY_OUT, one line each, for tests/test_lsp_neovim.py.
local out = {}
local file = vim.env.CYPHY_FILE
vim.cmd("edit " .. file)
local buf = vim.api.nvim_get_current_buf()
local client_id = vim.lsp.start_client({
  name = "cyphy",
  cmd = { vim.env.CYPHY_PYTHON, "-m", "cyphy", "lsp" },
  root_dir = vim.fn.fnamemodify(file, ":h"),
})
vim.lsp.buf_attach_client(buf, client_id)
vim.wait(60000, function() return #vim.diagnostic.get(buf) > 0 end, 50)
for _, d in ipairs(vim.diagnostic.get(buf)) do
  local code = d.code or (d.user_data and d.user_data.lsp and d.user_data.lsp.code) or "?"
  table.insert(out, string.format("diagnostic\t%s\t%d\t%d\t%d\t%d\t%s", code, d.lnum, d.col,
    d.end_lnum, d.end_col, (d.message:gsub("\n", "\\n"))))
end
local params = {
  textDocument = { uri = vim.uri_from_bufnr(buf) },
  position = { line = tonumber(vim.env.CYPHY_LINE), character = tonumber(vim.env.CYPHY_COL) },
}
local answers = vim.lsp.buf_request_sync(buf, "textDocument/definition", params, 30000) or {}
for _, answer in pairs(answers) do
  local loc = answer.result
  if loc and loc.uri then
    table.insert(out, string.format("definition\t%s\t%d", vim.uri_to_fname(loc.uri),
      loc.range.start.line))
  end
end
vim.fn.writefile(out, vim.env.CYPHY_OUT)
vim.lsp.stop_client(client_id)
vim.cmd("qall!")
